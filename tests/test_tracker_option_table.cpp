// The tracker option table (experiments/tracker_option_table.h) through the built `bivo`:
// every flag of `bivo run` given an invalid value is refused with the message the same value
// gets in a --config file, and the configuration written by an accepted run replays to a
// byte-identical trajectory (the Python side: tests/python/test_odometry.py).
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "experiments/tracker_config.h"
#include "experiments/tracker_option_table.h"
#include "tests/support/cli_suite.h"

namespace fs = std::filesystem;
using bivo::testing::contains;
using bivo::testing::slurp;
using namespace bivo;
using bivo::experiments::OptionType;
using bivo::experiments::TrackerOption;
using bivo::testing::BivoRun;
using json = nlohmann::json;

namespace {

class TrackerOptionSources : public bivo::testing::CliSuite {
 protected:
  static void SetUpTestSuite() { render_suite("bivo_option_table", {{"shared", 4, 5}}); }
};

// A flag text the option must refuse, and the JSON value a file would hold for it.
struct Bad {
  std::string text;
  json value;
};

std::vector<Bad> invalid_values(const TrackerOption& o) {
  std::vector<Bad> out;
  switch (o.type) {
    case OptionType::kNumber:
    case OptionType::kOptionalNumber: {
      double below = o.lo_open ? o.lo : o.lo - 1.0;
      if (o.auto_value && below == *o.auto_value) below = 0.5 * (o.lo + *o.auto_value);  // -1 would be "auto"
      out.push_back({experiments::format_option_number(below), below});
      if (std::isfinite(o.hi)) out.push_back({experiments::format_option_number(2 * o.hi + 1), 2 * o.hi + 1});
      out.push_back({"x1", "x1"});
      break;
    }
    case OptionType::kInteger:
      out.push_back({std::to_string(std::int64_t(o.lo) - 1), std::int64_t(o.lo) - 1});
      out.push_back({std::to_string(std::int64_t(o.hi) + 1), std::int64_t(o.hi) + 1});
      out.push_back({"2.5", 2.5});
      break;
    case OptionType::kBoolean:
      out.push_back({"maybe", "maybe"});
      break;
    case OptionType::kName:
      out.push_back({"nonsense", "nonsense"});
      break;
    case OptionType::kString:  // method and backend: names checked by odometry::validate (below)
      break;
    case OptionType::kIntrinsics:
      out.push_back({"0 525 319.5 239.5", {{"fx", 0.0}, {"fy", 525.0}, {"cx", 319.5}, {"cy", 239.5}}});
      out.push_back({"525 525 319.5 x", {{"fx", 525.0}, {"fy", 525.0}, {"cx", 319.5}, {"cy", "x"}}});
      break;
    case OptionType::kDistortion:
      out.push_back({"0 0 0 0 y", {{"k1", 0.0}, {"k2", 0.0}, {"p1", 0.0}, {"p2", 0.0}, {"k3", "y"}}});
      break;
  }
  return out;
}

// {"a": {"b": value}} for key "a.b".
json nested(const std::string& key, const json& value) {
  json j = json::object();
  std::string p = "/" + key;
  for (char& c : p) c = c == '.' ? '/' : c;
  j[json::json_pointer(p)] = value;
  return j;
}

}  // namespace

TEST(TrackerOptionTable, KeysFlagsAndPythonNamesAreUniqueAndEveryFieldIsWritten) {
  std::set<std::string> keys, flags, python;
  for (const auto& o : experiments::tracker_option_table()) {
    EXPECT_TRUE(keys.insert(o.key).second) << o.key;
    if (!o.flag.empty()) {
      EXPECT_TRUE(flags.insert(o.flag).second) << o.flag;
    }
    EXPECT_TRUE(python.insert(o.python_name()).second) << o.python_name();
  }
  // The writer's document has exactly the table's keys (nothing written that is not read).
  std::set<std::string> written;
  const std::function<void(const json&, const std::string&)> walk = [&](const json& j, const std::string& at) {
    for (auto it = j.begin(); it != j.end(); ++it) {
      const std::string key = at.empty() ? it.key() : at + "." + it.key();
      if (keys.count(key)) {
        written.insert(key);
      } else {
        ASSERT_TRUE(it->is_object()) << key;
        walk(*it, key);
      }
    }
  };
  walk(experiments::tracker_options_to_json({}), "");
  EXPECT_EQ(written, keys);
}

// A config {} names no method: a run from it alone is refused rather than run on a default.
TEST_F(TrackerOptionSources, AConfigWithoutAMethodIsRefused) {
  std::ofstream(dir_ / "empty.json") << "{}";
  const BivoRun r =
      bivo("run " + q(sequence_) + " --config " + q(dir_ / "empty.json") + " --output " + q(dir_ / "out.txt"));
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_TRUE(contains(r.err, "names no method")) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "out.txt"));
}

TEST_F(TrackerOptionSources, EveryInvalidFlagIsRefusedWithTheMessageOfTheFile) {
  int checked = 0;
  for (const auto& o : experiments::tracker_option_table()) {
    if (o.flag.empty()) continue;
    const std::string method = o.method.empty() ? "weighted" : o.method;
    for (const Bad& bad : invalid_values(o)) {
      // The file's message, without the file's name in front.
      json doc = nested(o.key, bad.value);
      doc["method"] = method;
      const std::string file_message =
          bivo::testing::error_of([&] { experiments::tracker_options_from_json(doc, "cfg.json"); });
      ASSERT_EQ(file_message.rfind("cfg.json: " + o.key, 0), 0u) << o.key << " " << bad.text << ": " << file_message;
      const std::string message = file_message.substr(std::string("cfg.json: ").size());

      const fs::path out = dir_ / "out.txt";
      const BivoRun flag =
          bivo("run " + q(sequence_) + " --method " + method + " " + o.flag + " '" + bad.text + "' --output " + q(out));
      EXPECT_EQ(flag.status, 1) << o.flag << " " << bad.text << ": " << flag.err;
      EXPECT_TRUE(contains(flag.err, "bivo: error: " + o.flag + ": " + message + "\n"))
          << o.flag << " " << bad.text << ": " << flag.err << " vs " << message;
      EXPECT_FALSE(fs::exists(out)) << o.flag;

      std::ofstream(dir_ / "cfg.json") << doc.dump();
      const BivoRun file = bivo("run " + q(sequence_) + " --config " + q(dir_ / "cfg.json") + " --output " + q(out));
      EXPECT_EQ(file.status, 1) << o.key << ": " << file.err;
      EXPECT_TRUE(contains(file.err, (dir_ / "cfg.json").string() + ": " + message + "\n")) << file.err;
      EXPECT_FALSE(fs::exists(out)) << o.key;
      ++checked;
    }
  }
  EXPECT_GE(checked, 80);  // every flag, most of them twice or three times
  // NaN cannot be written in a file; as a flag it is refused naming the range.
  const BivoRun nan = bivo("run " + q(sequence_) + " --method weighted --nu nan --output " + q(dir_ / "o.txt"));
  EXPECT_EQ(nan.status, 1);
  EXPECT_TRUE(contains(nan.err, "--nu: problem.weights.nu: nan is outside (0, inf]")) << nan.err;
}

// Every method, with its own parameters and general flags away from their defaults: the
// configuration the run writes gives the same trajectory, byte for byte, and holds the values.
TEST_F(TrackerOptionSources, TheConfigurationOfAnAcceptedRunReplaysByteIdentically) {
  const std::string common =
      " --levels 3 --nu 4.5 --step-tolerance 2e-5 --decrease-tolerance 3e-4 --scale-tolerance 2e-3"
      " --scale-iterations 7 --min-valid-pixels 150 --occlusion-margin 0.07 --max-dt 0.03 --threads 1"
      " --initial-guess identity --max-iterations 15 --intrinsics '520 521 319 240' --distortion none";
  const std::vector<std::string> methods = {"single",
                                            "depth",
                                            "fixed --lambda 2e4",
                                            "tykkala",
                                            "weighted --phi 50",
                                            "bounded --eps-min 2e-4 --eps-max 2e-3 --delta 0.03",
                                            "bounded --eps 5e-4 --backend ipm-compressed",
                                            "joint --joint-tolerance 1e-4",
                                            "scaled --kappa 0.05",
                                            "noise-bounded --eps-ratio 0.7 --guard 100",
                                            "weighted --weights huber --huber-k 1.5"};
  for (const std::string& m : methods) {
    const fs::path a = dir_ / "a.txt", b = dir_ / "b.txt";
    const BivoRun first = bivo("run " + q(sequence_) + " --method " + m + common + " --output " + q(a));
    ASSERT_EQ(first.status, 0) << m << ": " << first.err;
    const fs::path config = dir_ / "a.config.json";
    const json written = json::parse(slurp(config));
    EXPECT_EQ(written["problem"]["weights"]["nu"], 4.5) << m;
    EXPECT_EQ(written["levels"], 3) << m;
    EXPECT_EQ(written["intrinsics"]["fy"], 521.0) << m;
    const BivoRun replay = bivo("run " + q(sequence_) + " --config " + q(config) + " --output " + q(b));
    ASSERT_EQ(replay.status, 0) << m << ": " << replay.err;
    EXPECT_EQ(slurp(a), slurp(b)) << m;
    EXPECT_EQ(slurp(config), slurp(dir_ / "b.config.json")) << m;
    fs::remove(a), fs::remove(b), fs::remove(config), fs::remove(dir_ / "b.config.json");
  }
}

// A config nested 200,000 deep crashed `run` (the message dumped the value recursively): it is
// refused while it is read, and a structured value where a number belongs is named by type.
TEST_F(TrackerOptionSources, ADeepConfigIsRefusedNotACrash) {
  std::ofstream(dir_ / "deep.json") << "{\"method\": \"single\", \"policy\": {\"eps\": " << std::string(200000, '[')
                                    << std::string(200000, ']') << "}}";
  const BivoRun deep =
      bivo("run " + q(sequence_) + " --config " + q(dir_ / "deep.json") + " --output " + q(dir_ / "out.txt"));
  EXPECT_EQ(deep.status, 1) << deep.err;
  EXPECT_TRUE(contains(deep.err, "deep.json: values nested more than 16 levels deep")) << deep.err;
  EXPECT_FALSE(fs::exists(dir_ / "out.txt"));
  EXPECT_NE(bivo::testing::error_of([] {
              experiments::tracker_options_from_json(json::parse(R"({"policy": {"eps": [[1]]}})"), "c");
            }).find("c: policy.eps: must be a number, got an array"),
            std::string::npos);
}
