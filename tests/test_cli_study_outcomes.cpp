// What the study commands (table, sweep, report) leave behind and how they exit, through the
// built `bivo` on tiny rendered sequences: two sequences whose folders share a name keep both
// results; a failed cell writes the others and exits 1 (0 with --keep-going, the count still
// on the last line); usage errors exit 2, bad values 1; a run too short for one RPE window gives "too
// short" cells instead of a dead report.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/support/cli_suite.h"

namespace fs = std::filesystem;
using bivo::testing::contains;
using bivo::testing::slurp;
using namespace bivo;
using bivo::testing::BivoRun;
using json = nlohmann::json;

namespace {

std::string last_line(const std::string& text) {
  std::string t = text;
  while (!t.empty() && t.back() == '\n') t.pop_back();
  const auto nl = t.rfind('\n');
  return nl == std::string::npos ? t : t.substr(nl + 1);
}

class StudyOutcomes : public bivo::testing::CliSuite {
 protected:
  // Two renderings of one category with different seeds: same folder name, in syn1/ and syn2/.
  static void SetUpTestSuite() { render_suite("bivo_study_outcomes", {{"syn1", 10, 1}, {"syn2", 10, 2}}); }
};

}  // namespace

TEST_F(StudyOutcomes, TwoSequencesOfOneNameKeepBothResults) {
  ASSERT_EQ(fs::path(sequences_[0]).filename(), fs::path(sequences_[1]).filename());
  const fs::path out = dir_ / "out";
  const BivoRun r = bivo("table --sequences " + q(sequences_[0]) + " " + q(sequences_[1]) +
                         " --methods single --levels 2 --output " + q(out));
  ASSERT_EQ(r.status, 0) << r.err;
  const json results = json::parse(slurp(out / "results.json"));
  std::set<std::string> labels;
  for (const auto& cell : results) labels.insert(cell.at("sequence").get<std::string>());
  ASSERT_EQ(labels.size(), 2u) << results.dump();
  for (const auto& label : labels) {
    EXPECT_TRUE(contains(slurp(out / "tables.md"), label)) << label;  // both columns, by their own title
  }
  // Both trajectories written, each the run of its own sequence (the seeds move differently).
  std::vector<std::string> trajectories;
  for (const auto& e : fs::directory_iterator(out / "trajectories")) trajectories.push_back(slurp(e.path()));
  ASSERT_EQ(trajectories.size(), 2u);
  EXPECT_NE(trajectories[0], trajectories[1]);
}

TEST_F(StudyOutcomes, AFailedCellExitsOneAfterWritingTheOthers) {
  const std::string args = "table --sequences " + q(sequences_[0]) + " " + q(dir_ / "nonexistent") +
                           " --methods single --levels 2 --output ";
  const BivoRun r = bivo(args + q(dir_ / "out"));
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_TRUE(contains(last_line(r.err), "1 of 2 unit(s) failed")) << r.err;
  EXPECT_TRUE(contains(r.err, "nonexistent")) << r.err;
  const json results = json::parse(slurp(dir_ / "out" / "results.json"));
  ASSERT_EQ(results.size(), 2u);
  EXPECT_EQ(results[0].value("frames", 0), 10);  // the good cell is there
  EXPECT_FALSE(results[1].contains("frames"));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_ / "out" / "trajectories"), fs::directory_iterator{}), 1);

  const BivoRun kept = bivo(args + q(dir_ / "kept") + " --keep-going");
  EXPECT_EQ(kept.status, 0) << kept.err;
  EXPECT_TRUE(contains(last_line(kept.err), "1 of 2 unit(s) failed")) << kept.err;
  EXPECT_TRUE(fs::exists(dir_ / "kept" / "tables.md"));
}

TEST_F(StudyOutcomes, ASweepWithABadBackendExitsOne) {
  const BivoRun r = bivo("sweep --sequences " + q(sequences_[0]) +
                         " --lambda-points 1 --eps-points 1 --eps-backend nope --levels 2 --output " + q(dir_ / "out"));
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_TRUE(contains(r.err, "nope")) << r.err;
}

// A command line of the wrong shape exits 2; a value a flag refuses exits 1 naming flag and
// value, as the same value in a configuration or study file does, and so does a runtime error.
TEST_F(StudyOutcomes, UsageErrorsExitTwoBadValuesAndRuntimeErrorsOne) {
  EXPECT_EQ(bivo("table --methods single").status, 2);  // --sequences missing
  EXPECT_EQ(bivo("run " + q(sequences_[0]) + " --method single --no-such-flag").status, 2);
  EXPECT_EQ(bivo("no-such-command").status, 2);
  EXPECT_EQ(bivo("pareto " + q(sequences_[0]) + " --pair 0 --every 2 --output " + q(dir_ / "o")).status, 2);
  EXPECT_EQ(bivo("--help").status, 0);
  const std::vector<std::pair<std::string, std::string>> bad_values = {
      {"table --sequences a b --output " + q(dir_ / "o") + " --first-frame x", "--first-frame = x"},
      {"table --sequences a --output " + q(dir_ / "o") + " --delta 0", "--delta: Value 0 not in range"},
      {"merge " + q(dir_ / "no-such-study.json"), "File does not exist: " + (dir_ / "no-such-study.json").string()},
      {"--max-conic-size 0 conic x.json", "--max-conic-size: Value 0 not in range"},
      {"run " + q(sequences_[0]) + " --method single --levels 0", "--levels: levels: 0 is outside [1, 8]"},
      {"run " + q(dir_ / "missing") + " --method single", "missing"}};
  for (const auto& [args, message] : bad_values) {
    const BivoRun r = bivo(args);
    EXPECT_EQ(r.status, 1) << args << ": " << r.err;
    EXPECT_TRUE(contains(r.err, "bivo: error: ")) << args << ": " << r.err;
    EXPECT_TRUE(contains(r.err, message)) << args << ": " << r.err;
  }
  EXPECT_FALSE(fs::exists(dir_ / "o"));
}

// 10 frames are 0.3 s: no 1-s RPE window. The report still completes, saying so in its cells;
// with --delta 0.1 the same run has RPE values.
TEST_F(StudyOutcomes, ATenFrameReportCompletesWithTooShortCells) {
  const std::string args = "report --sequences " + q(sequences_[0]) +
                           " --methods single weighted --max-frames 10 --sweep-frames 10 --lambda-points 1"
                           " --eps-points 1 --pareto-points 3 --levels 2 --no-plots --output ";
  const BivoRun r = bivo(args + q(dir_ / "r1"));
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string report = slurp(dir_ / "r1" / "report.md");
  EXPECT_TRUE(contains(report, "| too short |")) << report;
  EXPECT_TRUE(contains(report, "fewer than 2 RPE windows of 1 s")) << report;

  const BivoRun shorter = bivo(args + q(dir_ / "r2") + " --delta 0.1");
  ASSERT_EQ(shorter.status, 0) << shorter.err;
  const std::string windows = slurp(dir_ / "r2" / "report.md");
  EXPECT_FALSE(contains(windows, "too short")) << windows;
  const json results = json::parse(slurp(dir_ / "r2" / "tables" / "results.json"));
  for (const auto& cell : results) EXPECT_GT(cell.value("rpe_windows", 0), 1) << cell.dump();
}

// --backend lm solves the lambda sweep by another algorithm: the same weighted-sum minima (the
// default gn run is the oracle) reached by different iterates, so not bit-identical.
TEST_F(StudyOutcomes, ParetoBackendAndBoundedCounts) {
  const std::string args = "pareto " + q(sequences_[0]) + " --pair 0 --points 5 --levels 2 --level 1 --no-plots";
  ASSERT_EQ(bivo(args + " --output " + q(dir_ / "gn")).status, 0);
  const BivoRun lm = bivo(args + " --backend lm --output " + q(dir_ / "lm"));
  ASSERT_EQ(lm.status, 0) << lm.err;
  EXPECT_TRUE(contains(slurp(dir_ / "lm" / "study.json"), "\"backend\": \"lm\""));
  const json a = json::parse(slurp(dir_ / "gn" / "pareto_pair0.json")).at("lambda_sweep");
  const json b = json::parse(slurp(dir_ / "lm" / "pareto_pair0.json")).at("lambda_sweep");
  bool identical = true;
  int matched = 0;  // the fronts keep their non-dominated points: compare those of equal lambda
  for (const auto& pa : a) {
    for (const auto& pb : b) {
      if (pa["lambda"] != pb["lambda"]) continue;
      const double lambda = pa["lambda"];
      const double fa = pa["f_i"].get<double>() + lambda * pa["f_d"].get<double>();
      const double fb = pb["f_i"].get<double>() + lambda * pb["f_d"].get<double>();
      EXPECT_NEAR(fb / fa, 1.0, 1e-5) << lambda;
      identical = identical && pa["f_i"] == pb["f_i"];
      ++matched;
    }
  }
  EXPECT_GE(matched, 2);
  EXPECT_FALSE(identical) << "the lambda sweep did not use --backend lm";

  const BivoRun bad = bivo(args + " --backend nope --output " + q(dir_ / "bad"));
  EXPECT_EQ(bad.status, 1);
  EXPECT_TRUE(contains(bad.err, "unknown solver backend 'nope'")) << bad.err;
  for (const char* points : {"100000", "2147483647", "99999999999"}) {  // ran without bound; then exited 2
    const BivoRun many = bivo(args + " --points " + points + " --output " + q(dir_ / "many"));
    EXPECT_EQ(many.status, 1) << many.err;
    EXPECT_TRUE(contains(many.err, std::string("--points: Value ") + points + " not in range 2 to 1000")) << many.err;
    EXPECT_FALSE(fs::exists(dir_ / "many"));
  }
  const BivoRun plan = bivo("plan pareto " + q(sequences_[0]) + " --pair 0 --points 3 --output " + q(dir_ / "p") +
                            " --study " + q(dir_ / "p.json"));
  ASSERT_EQ(plan.status, 0) << plan.err;
  const BivoRun shard = bivo("work " + q(dir_ / "p.json") + " --shard 0/99999999999");
  EXPECT_EQ(shard.status, 1);
  EXPECT_TRUE(contains(shard.err, "--shard '0/99999999999'")) << shard.err;
}
