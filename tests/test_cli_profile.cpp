// `bivo profile` through the built binary on a tiny rendered sequence: the reference
// (single with Gauss-Newton) is timed and printed once, first, wherever it is listed; every
// method is timed over the repetitions asked for, with median and quartiles. (Timings
// themselves are not asserted: a test must not depend on the machine's load.)
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/support/cli_suite.h"

namespace fs = std::filesystem;
using namespace bivo;
using json = nlohmann::json;

namespace {

class CliProfile : public bivo::testing::CliSuite {
 protected:
  static void SetUpTestSuite() { render_suite("bivo_cli_profile", {{"", 4, 1}}); }
};

}  // namespace

TEST_F(CliProfile, TheReferenceIsTimedOnceFirstAndEveryMethodOverTheRepetitions) {
  const bivo::testing::BivoRun r =
      bivo("profile " + q(sequence_) + " --methods weighted single:gn fixed --repetitions 2 --levels 2 --output " +
           q(dir_ / "out"));
  ASSERT_EQ(r.status, 0) << r.err;
  std::ifstream in(dir_ / "out" / "profile.json");
  const json rows = json::parse(in);
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0]["method"], "single");
  EXPECT_EQ(rows[0]["backend"], "gn");
  EXPECT_EQ(rows[1]["method"], "weighted");
  EXPECT_EQ(rows[2]["method"], "fixed");
  for (const auto& row : rows) {
    EXPECT_EQ(row["repetitions"], 2) << row.dump();
    EXPECT_EQ(row["pairs"], 3) << row.dump();
    EXPECT_LE(row["q1_ms"].get<double>(), row["median_ms"].get<double>());
    EXPECT_LE(row["median_ms"].get<double>(), row["q3_ms"].get<double>());
  }
  // The reference's row of the runtime table is printed once.
  std::ifstream md(dir_ / "out" / "profile.md");
  std::stringstream text;
  text << md.rdbuf();
  const std::string s = text.str();
  const std::string runtime = s.substr(s.find("Runtime per frame pair"));
  EXPECT_EQ(runtime.find("| single | gn |"), runtime.rfind("| single | gn |")) << runtime;
  EXPECT_NE(runtime.find("| single | gn | 3 x 2 |"), std::string::npos) << runtime;
}
