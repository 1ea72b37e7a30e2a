// Every input under tests/fuzz/regressions/<harness>/ (crashes the fuzzers found, and the
// reproducers) replayed through its harness in every build: a regression
// crashes or throws something other than bivo::Error here. The seed corpus the fuzzers
// start from must be accepted by the readers, or fuzzing would start from garbage.
#include <filesystem>
#include <fstream>
#include <iterator>

#include <gtest/gtest.h>

#include "experiments/conic_files/cbf_file.h"
#include "experiments/conic_files/conic_file.h"
#include "harnesses.h"
#include "odometry/io/png_io.h"
#include "odometry/io/trajectory.h"
#include "odometry/io/tum_dataset.h"

namespace fs = std::filesystem;

namespace {

std::string bytes_of(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Runs every file of `dir` through the harness; returns how many there were.
int replay(const bivo::fuzz::Harness& h, const fs::path& dir) {
  int count = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string data = bytes_of(e.path());
    SCOPED_TRACE(e.path().string());
    EXPECT_NO_THROW(h.run(reinterpret_cast<const std::uint8_t*>(data.data()), data.size()));
    ++count;
  }
  return count;
}

}  // namespace

TEST(FuzzRegressions, EveryStoredInputIsRejectedOrAcceptedCleanly) {
  for (const auto& h : bivo::fuzz::harnesses()) {
    const fs::path dir = fs::path(BIVO_FUZZ_REGRESSIONS) / h.name;
    ASSERT_TRUE(fs::is_directory(dir)) << dir;
    EXPECT_GT(replay(h, dir), 0) << dir;
  }
}

TEST(FuzzRegressions, SeedsAreValidInputs) {
  const fs::path dir = fs::path(::testing::TempDir()) / "bivo_fuzz_seeds";
  fs::remove_all(dir);
  bivo::fuzz::write_seeds(dir.string());
  for (const auto& h : bivo::fuzz::harnesses()) EXPECT_GT(replay(h, dir / h.name), 1) << h.name;
  EXPECT_EQ(bivo::odometry::io::read_file_list((dir / "tum_list" / "rgb.txt").string()).size(), 3u);
  EXPECT_EQ(bivo::odometry::io::read_tum_trajectory((dir / "trajectory" / "groundtruth.txt").string()).size(), 3u);
  EXPECT_EQ(bivo::odometry::io::read_png8((dir / "png" / "rgb.png").string()).channels, 3);
  EXPECT_EQ(bivo::odometry::io::read_png16((dir / "png" / "depth.png").string()).width, 12);
  // The CBF writer of the seeds against the JSON reader: the same LP, min -x1 - x2 s.t.
  // x1 + 2 x2 <= 4, 3 x1 + x2 <= 6, x >= 0, optimum -2.8 at (1.6, 1.2), from both files.
  const bivo::experiments::CbfProblem cbf = bivo::experiments::read_cbf((dir / "cbf" / "lp_dense.cbf").string());
  const auto json = bivo::experiments::read_conic_json((dir / "conic_json" / "lp_dense.json").string());
  for (const auto* p : {&cbf.problem, &json}) {
    const auto r = bivo::solvers::conic::solve_conic(*p);
    ASSERT_EQ(r.status, bivo::solvers::conic::IpmStatus::kOptimal);
    EXPECT_NEAR(r.primal_objective, -2.8, 1e-7);
    EXPECT_NEAR(r.x[0], 1.6, 1e-6);
    EXPECT_NEAR(r.x[1], 1.2, 1e-6);
  }
  EXPECT_EQ(bivo::experiments::read_cbf((dir / "cbf" / "paper_socp_full.cbf").string()).problem.cones.soc.size(), 2u);
  EXPECT_FALSE(fs::exists(dir / "sequence"));
  fs::remove_all(dir);
}
