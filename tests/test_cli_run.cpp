// `bivo run` through the built binary (BIVO_BINARY) on a tiny rendered sequence (no data
// needed): output formats, the first pose taken from ground truth, and bad input (unknown
// method or backend, a backend that cannot solve the method, options of another method,
// missing sequence, unwritable output) -> exit 1, a clear message and no file left behind.
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include <gtest/gtest.h>

#include "odometry/io/trajectory.h"
#include "tests/support/cli_suite.h"

namespace fs = std::filesystem;
using namespace bivo;
using bivo::testing::BivoRun;
using bivo::testing::slurp;

namespace {

// One 4-frame synthetic sequence shared by all tests of this file.
class CliRun : public bivo::testing::CliSuite {
 protected:
  static void SetUpTestSuite() {
    render_suite("bivo_cli_run", {{"", 4, 3, odometry::synth::SynthOptions{}.render.supersampling}});
  }
  std::string seq() const { return q(sequence_); }
  void expect_no_leftovers() const {
    for (const auto& e : fs::directory_iterator(dir_)) ADD_FAILURE() << "left behind: " << e.path();
  }
};

}  // namespace

TEST_F(CliRun, WritesTrajectoryLogAndEndsWithTheRunLine) {
  const BivoRun r =
      bivo("run " + seq() + " --method single --output " + q(dir_ / "traj.txt") + " --log " + q(dir_ / "pairs.csv"));
  ASSERT_EQ(r.status, 0) << r.err;
  // The last line of stdout is the run line; no progress bar on a non-terminal stderr.
  const std::regex line(
      R"((^|\n)frames=4 median_ms=[0-9.]+ mean_ms=[0-9.]+ median_cpu_ms=[0-9.]+ mean_cpu_ms=[0-9.]+ failures=0\n$)");
  EXPECT_TRUE(std::regex_search(r.out, line)) << r.out;
  EXPECT_EQ(r.err.find('\r'), std::string::npos) << r.err;

  const auto est = odometry::io::read_tum_trajectory((dir_ / "traj.txt").string());
  const auto gt = odometry::io::read_tum_trajectory(sequence_ + "/groundtruth.txt");
  ASSERT_EQ(est.size(), 4u);
  // One pose per rgb frame at the frame's timestamp; the first one is the ground truth's.
  std::vector<double> rgb_stamps;
  std::istringstream rgb(slurp(sequence_ + "/rgb.txt"));
  for (std::string l; std::getline(rgb, l);) {
    if (!l.empty() && l[0] != '#') rgb_stamps.push_back(std::stod(l));
  }
  ASSERT_EQ(rgb_stamps.size(), 4u);
  for (size_t k = 0; k < 4; ++k) EXPECT_NEAR(est[k].timestamp, rgb_stamps[k], 1e-6);
  EXPECT_LT((est[0].T_wc.matrix() - gt[0].T_wc.matrix()).norm(), 1e-6);

  const std::string log = slurp(dir_ / "pairs.csv");
  EXPECT_EQ(std::count(log.begin(), log.end(), '\n'), 4);  // header + 3 pairs
  EXPECT_EQ(log.rfind("pair,t_reference,t_current,valid,iterations,ms", 0), 0u) << log;
}

TEST_F(CliRun, StartFrameAndMaxFramesSelectTheWindow) {
  const BivoRun r =
      bivo("run " + seq() + " --method weighted --first-frame 1 --max-frames 2 --output " + q(dir_ / "t.txt"));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("frames=2 "), std::string::npos) << r.out;
  EXPECT_EQ(odometry::io::read_tum_trajectory((dir_ / "t.txt").string()).size(), 2u);
}

TEST_F(CliRun, UnknownMethodListsTheValidOnes) {
  const BivoRun r = bivo("run " + seq() + " --method newton --output " + q(dir_ / "t.txt"));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("newton"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("bounded"), std::string::npos) << r.err;
  expect_no_leftovers();
}

TEST_F(CliRun, UnknownBackendListsTheValidOnes) {
  const BivoRun r = bivo("run " + seq() + " --method bounded --backend cvxpy --output " + q(dir_ / "t.txt"));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("cvxpy"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("exact"), std::string::npos) << r.err;
  expect_no_leftovers();
}

TEST_F(CliRun, BackendThatCannotSolveTheMethodFails) {
  // gn solves weighted sums only; bounded is an epsilon-constraint.
  const BivoRun r = bivo("run " + seq() + " --method bounded --backend gn --output " + q(dir_ / "t.txt"));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("gn"), std::string::npos) << r.err;
  expect_no_leftovers();
}

TEST_F(CliRun, OptionOfAnotherMethodFails) {
  const BivoRun r = bivo("run " + seq() + " --method single --lambda 10");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("--lambda"), std::string::npos) << r.err;
}

TEST_F(CliRun, MissingSequenceIsNamed) {
  const BivoRun r = bivo("run " + q(dir_ / "nowhere") + " --method single");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("nowhere"), std::string::npos) << r.err;
}

TEST_F(CliRun, UnwritableOutputFailsAndLeavesNothing) {
  const fs::path target = dir_ / "missing_dir" / "traj.txt";
  const BivoRun r = bivo("run " + seq() + " --method single --max-frames 2 --output " + q(target));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("traj.txt"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(target));
  expect_no_leftovers();
}

TEST_F(CliRun, EverySubcommandHasHelp) {
  for (const char* sub : {"run", "eval", "table", "sweep", "pareto", "profile", "report", "demo"}) {
    const BivoRun r = bivo(std::string(sub) + " --help");
    EXPECT_EQ(r.status, 0) << sub;
    EXPECT_NE(r.out.find("Usage"), std::string::npos) << sub << ": " << r.out;
  }
}

// Flags -> configuration file -> run reproduces the trajectory byte for byte.
TEST_F(CliRun, ConfigRoundTripGivesByteIdenticalTrajectories) {
  const std::string flags =
      " --method bounded --eps-min 2e-4 --eps-max 2e-3 --delta 0.015 --levels 3 --finest-level 1 --nu 4.5"
      " --initial-guess identity --max-iterations 9 --step-tolerance 3e-4 --decrease-tolerance 2e-3"
      " --min-depth 0.2 --max-depth 8 --occlusion-margin 0.05 --max-dt 0.015 --intrinsics '535.4 539.2 320.1 247.6'"
      " --distortion '0.05 -0.1 0.001 0.002 0.01' --first-frame 1 --max-frames 3";
  const BivoRun a =
      bivo("run " + seq() + flags + " --output " + q(dir_ / "a.txt") + " --save-config " + q(dir_ / "saved.json"));
  ASSERT_EQ(a.status, 0) << a.err;
  const std::string config = slurp(dir_ / "a.config.json");
  ASSERT_FALSE(config.empty());
  EXPECT_EQ(slurp(dir_ / "saved.json"), config);
  for (const char* value : {"\"finest_level\": 1", "\"nu\": 4.5", "\"eps_min\": 0.0002", "\"first_frame\": 1",
                            "\"max_frames\": 3", "\"initial_guess\": \"identity\"", "\"fx\": 535.4", "\"k1\": 0.05"}) {
    EXPECT_NE(config.find(value), std::string::npos) << value << " missing in\n" << config;
  }
  const BivoRun b = bivo("run " + seq() + " --config " + q(dir_ / "a.config.json") + " --output " + q(dir_ / "b.txt"));
  ASSERT_EQ(b.status, 0) << b.err;
  EXPECT_EQ(slurp(dir_ / "b.txt"), slurp(dir_ / "a.txt"));
  EXPECT_EQ(slurp(dir_ / "b.config.json"), config);
  // Changing one field changes the result: the file is really read.
  const BivoRun c = bivo("run " + seq() + " --config " + q(dir_ / "a.config.json") +
                         " --initial-guess constant-velocity --output " + q(dir_ / "c.txt"));
  ASSERT_EQ(c.status, 0) << c.err;
  EXPECT_NE(slurp(dir_ / "c.txt"), slurp(dir_ / "a.txt"));
  EXPECT_NE(slurp(dir_ / "c.config.json").find("\"initial_guess\": \"constant-velocity\""), std::string::npos);
  EXPECT_NE(slurp(dir_ / "c.config.json").find("\"eps_min\": 0.0002"), std::string::npos);
}

// The data-driven policies' fields take the same road: flags -> file -> run.
// One method, two frames: each bivo process costs about a second on CI (kappa and
// joint_weights round-trip through the file in TrackerConfig.EveryFieldRoundTrips...).
TEST_F(CliRun, NewPolicyFieldsRoundTripThroughTheConfig) {
  const std::string flags = " --method noise-bounded --eps-ratio 0.7 --guard 0.03 --levels 2 --finest-level 1";
  const BivoRun a = bivo("run " + seq() + flags + " --max-frames 2 --output " + q(dir_ / "a.txt"));
  ASSERT_EQ(a.status, 0) << a.err;
  const std::string config = slurp(dir_ / "a.config.json");
  EXPECT_NE(config.find("\"eps_ratio\": 0.7"), std::string::npos) << config;
  EXPECT_NE(config.find("\"guard\": 0.03"), std::string::npos) << config;
  const BivoRun b = bivo("run " + seq() + " --config " + q(dir_ / "a.config.json") + " --output " + q(dir_ / "b.txt"));
  ASSERT_EQ(b.status, 0) << b.err;
  EXPECT_EQ(slurp(dir_ / "b.txt"), slurp(dir_ / "a.txt"));
  EXPECT_EQ(slurp(dir_ / "b.config.json"), config);
  // A policy flag of another method is refused, naming its method.
  const BivoRun bad = bivo("run " + seq() + " --method joint --kappa 2 --output " + q(dir_ / "x.txt"));
  EXPECT_NE(bad.status, 0);
  EXPECT_NE(bad.err.find("scaled"), std::string::npos) << bad.err;
}

TEST_F(CliRun, BadConfigFileNamesTheKeyAndWritesNothing) {
  std::ofstream(dir_ / "cfg.json") << R"({"method": "single", "levles": 3})";
  const BivoRun r = bivo("run " + seq() + " --config " + q(dir_ / "cfg.json") + " --output " + q(dir_ / "t.txt"));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("cfg.json: unknown key 'levles'"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "t.txt"));
  EXPECT_FALSE(fs::exists(dir_ / "t.config.json"));
  const BivoRun m = bivo("run " + seq() + " --output " + q(dir_ / "t.txt"));
  EXPECT_EQ(m.status, 1);
  EXPECT_NE(m.err.find("--method"), std::string::npos) << m.err;
}
