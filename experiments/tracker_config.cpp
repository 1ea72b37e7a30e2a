// TrackerOptions <-> JSON (tracker_config.h).
#include "experiments/tracker_config.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <set>

#include "experiments/tracker_option_table.h"
#include "odometry/io/atomic_file.h"
#include "odometry/io/json_file.h"
#include "solvers/error.h"

namespace bivo::experiments {

namespace {

using json = nlohmann::json;
using odometry::TrackerOptions;

// The value at `key` ("problem.weights.nu" -> j["problem"]["weights"]["nu"]), nullptr when absent.
const json* value_at(const json& j, const std::string& key) {
  const json* node = &j;
  std::size_t begin = 0;
  for (;;) {
    const std::size_t dot = key.find('.', begin);
    const auto it = node->find(key.substr(begin, dot == std::string::npos ? std::string::npos : dot - begin));
    if (it == node->end()) return nullptr;
    if (dot == std::string::npos) return &*it;
    if (!it->is_object()) return nullptr;  // refused by check_keys
    node = &*it;
    begin = dot + 1;
  }
}

// Every key of `j` (at `prefix`) is an option of the table or an object holding some; a
// typo in a hand-edited file is an error, not a silently ignored key.
void check_keys(const json& j, const std::string& prefix, const std::string& where) {
  if (!j.is_object()) {
    throw Error(where + ": " + (prefix.empty() ? "" : prefix + ": ") + "must be a JSON object, got " + j.type_name());
  }
  const std::string head = prefix.empty() ? "" : prefix + ".";
  std::set<std::string> valid;  // the names allowed at this level
  for (const auto& o : tracker_option_table()) {
    if (o.key.rfind(head, 0) == 0) valid.insert(o.key.substr(head.size(), o.key.find('.', head.size()) - head.size()));
  }
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (!valid.count(it.key())) {
      std::string names;
      for (const auto& v : valid) names += (names.empty() ? "" : ", ") + v;
      throw Error(where + ": unknown key '" + head + it.key() + "' (valid: " + names + ")");
    }
    if (!find_tracker_option_by_key(head + it.key())) check_keys(it.value(), head + it.key(), where);
  }
}

// A configuration is a few levels deep; a document nested thousands deep is refused while it
// is read, before anything recurses through it.
constexpr int kMaxConfigDepth = 16;

}  // namespace

json tracker_options_to_json(const TrackerOptions& o) {
  json j = json::object();
  for (const auto& option : tracker_option_table()) {
    j[json::json_pointer("/" + [&] {
      std::string p = option.key;
      for (char& c : p) c = c == '.' ? '/' : c;
      return p;
    }())] = option.get(o);
  }
  return j;
}

TrackerOptions tracker_options_from_json(const json& j, const std::string& where, const TrackerOptions& base) {
  check_keys(j, "", where);
  TrackerOptions o = base;
  for (const auto& option : tracker_option_table()) {
    const json* v = value_at(j, option.key);
    if (!v) continue;
    try {
      apply_tracker_option(option, *v, o);
    } catch (const Error& e) {
      throw Error(where + ": " + e.what());
    }
  }
  try {
    odometry::validate(o);
  } catch (const Error& e) {
    throw Error(where + ": " + e.what());
  }
  return o;
}

TrackerOptions read_tracker_config(const std::string& path, const TrackerOptions& base) {
  return tracker_options_from_json(odometry::io::read_json_file(path, "tracker configuration", kMaxConfigDepth), path,
                                   base);
}

bool tracker_config_names_method(const std::string& path) {
  json j;
  try {
    j = odometry::io::read_json_file(path, "tracker configuration", kMaxConfigDepth);
  } catch (const Error&) {
    return false;
  }
  return j.is_object() && j.contains("method");
}

void write_tracker_config(const std::string& path, const TrackerOptions& options) {
  const std::string text = tracker_options_to_json(options).dump(2) + "\n";
  odometry::io::write_file_atomically(path, [&](std::ostream& out) { out << text; });
}

}  // namespace bivo::experiments
