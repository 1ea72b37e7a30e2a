#pragma once
// Strict reading of one JSON object, shared by the configuration files (tracker_config.h)
// and the study files (study.h): typed getters that name the key's path in their errors,
// and reject_unknown() refuses every key nobody asked for, so a typo in a hand-edited file
// is an error instead of being ignored.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "solvers/error.h"

namespace bivo::experiments {

class JsonObjectReader {
 public:
  using json = nlohmann::json;

  // `where` names the object in errors ("config.json.problem").
  JsonObjectReader(const json& j, std::string where) : j_(j), where_(std::move(where)) {
    if (!j_.is_object()) throw Error(where_ + ": must be a JSON object, got " + j_.type_name());
  }

  std::string path(const char* key) const { return where_ + "." + key; }
  // The value of `key`, or nullptr; either way `key` is known from now on.
  const json* find(const char* key) {
    known_.insert(key);
    const auto it = j_.find(key);
    return it == j_.end() ? nullptr : &*it;
  }
  const json& need(const char* key) {
    const json* v = find(key);
    if (!v) throw Error(where_ + ": missing key '" + key + "'");
    return *v;
  }

  // Optional keys: `out` keeps its value when the key is absent.
  void number(const char* key, double& out, double lo, double hi) {
    const json* v = find(key);
    if (!v) return;
    if (!v->is_number()) throw Error(path(key) + ": must be a number, got " + v->type_name());
    const double d = v->get<double>();
    if (!std::isfinite(d) || d < lo || d > hi) {
      throw Error(path(key) + ": " + v->dump() + " is outside [" + bound(lo) + ", " + bound(hi) + "]");
    }
    out = d;
  }
  void integer(const char* key, int& out, int lo, int hi) {
    const json* v = find(key);
    if (!v) return;
    if (!v->is_number_integer()) throw Error(path(key) + ": must be an integer, got " + v->dump());
    const auto i = v->get<std::int64_t>();
    if (i < lo || i > hi) {
      throw Error(path(key) + ": " + v->dump() + " is outside [" + std::to_string(lo) + ", " + std::to_string(hi) +
                  "]");
    }
    out = static_cast<int>(i);
  }
  void boolean(const char* key, bool& out) {
    const json* v = find(key);
    if (!v) return;
    if (!v->is_boolean()) throw Error(path(key) + ": must be true or false, got " + v->dump());
    out = v->get<bool>();
  }
  void string(const char* key, std::string& out) {
    const json* v = find(key);
    if (!v) return;
    if (!v->is_string()) throw Error(path(key) + ": must be a string, got " + v->type_name());
    out = v->get<std::string>();
  }
  // An enum by name, parsed by the layer's own parse function (its error lists valid names).
  template <class Enum, class Parse>
  void name(const char* key, Enum& out, Parse parse) {
    if (!find(key)) return;
    std::string s;
    string(key, s);
    try {
      out = parse(s);
    } catch (const Error& e) {
      throw Error(path(key) + ": " + e.what());
    }
  }

  // Required keys: a missing one is an error.
  std::string string(const char* key) {
    need(key);
    std::string s;
    string(key, s);
    return s;
  }
  int integer(const char* key, int lo) {
    need(key);
    int i = lo;
    integer(key, i, lo, INT32_MAX);
    return i;
  }
  double number(const char* key) {
    const json& v = need(key);
    if (!v.is_number()) throw Error(path(key) + ": must be a number, got " + v.dump());
    return v.get<double>();
  }
  bool boolean(const char* key) {
    need(key);
    bool b = false;
    boolean(key, b);
    return b;
  }
  const json& array(const char* key) {
    const json& v = need(key);
    if (!v.is_array()) throw Error(path(key) + ": must be an array, got " + v.type_name());
    return v;
  }
  std::vector<std::string> strings(const char* key) {
    std::vector<std::string> out;
    for (const json& v : array(key)) {
      if (!v.is_string()) throw Error(path(key) + ": every entry must be a string, got " + v.dump());
      out.push_back(v.get<std::string>());
    }
    return out;
  }
  std::vector<double> numbers(const char* key) {
    std::vector<double> out;
    for (const json& v : array(key)) {
      if (!v.is_number()) throw Error(path(key) + ": every entry must be a number, got " + v.dump());
      out.push_back(v.get<double>());
    }
    return out;
  }

  void reject_unknown() const {
    for (auto it = j_.begin(); it != j_.end(); ++it) {
      if (!known_.count(it.key())) {
        std::string valid;
        for (const auto& k : known_) valid += (valid.empty() ? "" : ", ") + k;
        throw Error(where_ + ": unknown key '" + it.key() + "' (valid: " + valid + ")");
      }
    }
  }

 private:
  static std::string bound(double v) {
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
  }

  const json& j_;
  std::string where_;
  std::set<std::string> known_;
};

}  // namespace bivo::experiments
