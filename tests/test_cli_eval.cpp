// `bivo eval` end to end through the built binary (BIVO_BINARY): the one-line output agrees
// with the library on a hand-built oracle, and bad input (no overlap, malformed lines,
// missing files, unwritable output) exits non-zero with a clear message and no file left.

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include <gtest/gtest.h>

#include "test_support.h"

namespace fs = std::filesystem;

namespace {

// Runs the bivo binary with `args` (shell-quoted by the caller), capturing stdout/stderr.
bivo::testing::BivoRun run_bivo(const std::string& args, const fs::path& dir) {
  return bivo::testing::run_bivo_in(args, dir.string());
}

class CliEval : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("bivo_cli_eval_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Truth moving along x at 0.5 m/s sampled at 100 Hz; estimate at 25 Hz with an extra
  // 0.05 m/s drift along y: every 1-s window has error exactly 0.05 m (docs/metrics.md).
  void write_pair(double est_offset_s = 0.0) {
    std::ofstream g(dir_ / "gt.txt"), e(dir_ / "est.txt");
    g.precision(17);
    e.precision(17);
    g << "# ground truth\n";
    for (int k = 0; k < 400; ++k) {
      const double t = k / 100.0;
      g << 1000.0 + t << " " << 0.5 * t << " 0 1 0 0 0 1\n";
    }
    for (int k = 0; k < 100; ++k) {
      const double t = k / 25.0;
      e << 1000.0 + t + est_offset_s << " " << 0.5 * t << " " << 0.05 * t << " 1 0 0 0 1\n";
    }
  }
  std::string q(const fs::path& p) const { return "'" + p.string() + "'"; }
  fs::path dir_;
};

}  // namespace

TEST_F(CliEval, PrintsExactlyOneLineWithTheOracleValues) {
  write_pair();
  const bivo::testing::BivoRun r = run_bivo("eval " + q(dir_ / "gt.txt") + " " + q(dir_ / "est.txt"), dir_);
  ASSERT_EQ(r.status, 0) << r.err;
  std::smatch m;
  const std::regex line(R"(^rpe_trans=(\S+) rpe_rot=(\S+) ate=(\S+) pairs=(\d+)\n$)");
  ASSERT_TRUE(std::regex_match(r.out, m, line)) << "stdout: '" << r.out << "'";
  EXPECT_NEAR(std::stod(m[1]), 0.05, 1e-6);
  EXPECT_NEAR(std::stod(m[2]), 0.0, 1e-6);
  EXPECT_EQ(std::stoi(m[4]), 100 - 26);  // n - k - 1 windows (docs/metrics.md)
  // ATE of a linear drift after the best rigid fit is positive and well below the end drift.
  EXPECT_GT(std::stod(m[3]), 0.0);
  EXPECT_LT(std::stod(m[3]), 0.05 * 4);
}

TEST_F(CliEval, JsonFlagAndOutputFile) {
  write_pair();
  const bivo::testing::BivoRun r = run_bivo(
      "eval --json --output " + q(dir_ / "detail.json") + " " + q(dir_ / "gt.txt") + " " + q(dir_ / "est.txt"), dir_);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("\"rpe_trans\":0.05"), std::string::npos) << r.out;
  ASSERT_TRUE(fs::exists(dir_ / "detail.json"));
  std::ifstream in(dir_ / "detail.json");
  std::stringstream s;
  s << in.rdbuf();
  EXPECT_NE(s.str().find("\"windows\""), std::string::npos);
}

TEST_F(CliEval, NoOverlappingTimestampsFails) {
  write_pair(/*est_offset_s=*/50.0);
  const bivo::testing::BivoRun r = run_bivo("eval " + q(dir_ / "gt.txt") + " " + q(dir_ / "est.txt"), dir_);
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_NE(r.err.find("overlap"), std::string::npos) << r.err;
}

TEST_F(CliEval, MalformedLineNamesFileAndLine) {
  write_pair();
  {
    std::ofstream e(dir_ / "est.txt", std::ios::app);
    e << "1004.5 1 2 three 0 0 0 1\n";
  }
  const bivo::testing::BivoRun r = run_bivo("eval " + q(dir_ / "gt.txt") + " " + q(dir_ / "est.txt"), dir_);
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("est.txt:101"), std::string::npos) << r.err;
}

TEST_F(CliEval, MissingFileFails) {
  write_pair();
  const bivo::testing::BivoRun r = run_bivo("eval " + q(dir_ / "gt.txt") + " " + q(dir_ / "nope.txt"), dir_);
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("nope.txt"), std::string::npos) << r.err;
}

TEST_F(CliEval, UnwritableOutputFailsAndLeavesNothing) {
  write_pair();
  const fs::path target = dir_ / "no_such_dir" / "detail.json";
  const bivo::testing::BivoRun r =
      run_bivo("eval --output " + q(target) + " " + q(dir_ / "gt.txt") + " " + q(dir_ / "est.txt"), dir_);
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("detail.json"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(target));
  // Nothing half-written beside the files either (temporaries are named "<target>.tmp*").
  for (const auto& entry : fs::directory_iterator(dir_)) {
    EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos) << entry.path();
  }
}

TEST_F(CliEval, MissingArgumentsIsAUsageError) {
  const bivo::testing::BivoRun r = run_bivo("eval", dir_);
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.err.find("groundtruth"), std::string::npos) << r.err;
}
