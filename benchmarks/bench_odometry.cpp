// Milliseconds per frame pair of each odometry method at 640x480 on real TUM frames
// (fr1/desk frames 0 -> 1, 4 pyramid levels, identity start), plus the building blocks:
// frame preparation (pyramid + statistics) and one level-0 linearization.
// Targets (one core): weighted sum <= 8 ms per pair, bounded <= 1.15 x weighted sum.
#include <filesystem>
#include <memory>
#include <string>

#include <benchmark/benchmark.h>

#include "odometry/tracker.h"
#include "solvers/se3.h"

namespace {

using namespace bivo::odometry;
using namespace bivo::odometry::io;

const std::string kSequence = std::string(BIVO_SHARED_DIR) + "/data/tum/rgbd_dataset_freiburg1_desk";

// Loaded once; null when the shared data is absent.
const FramePair* shared_pair() {
  static std::unique_ptr<FramePair> pair = [] {
    if (!std::filesystem::exists(kSequence)) return std::unique_ptr<FramePair>();
    TrackerOptions o;
    return std::make_unique<FramePair>(load_frame_pair(kSequence, 0, 1, o));
  }();
  return pair.get();
}

void BM_OdometryPair(benchmark::State& state, const std::string& method, const std::string& backend) {
  const FramePair* pair = shared_pair();
  if (!pair) {
    state.SkipWithError(("shared data absent: " + kSequence).c_str());
    return;
  }
  TrackerOptions o;
  o.method = method;
  o.backend = backend;
  int iterations = 0;
  for (auto _ : state) {
    const PairResult r = estimate_motion(pair->reference, pair->current, Eigen::Isometry3d::Identity(), o);
    iterations = r.iterations;
    benchmark::DoNotOptimize(r.T_21);
  }
  state.counters["outer_iterations"] = iterations;
}

void BM_OdometryPrepareFrame(benchmark::State& state) {
  if (!std::filesystem::exists(kSequence)) {
    state.SkipWithError(("shared data absent: " + kSequence).c_str());
    return;
  }
  const TumSequence seq = open_tum_sequence(kSequence);
  const RgbdImage image = load_rgbd_image(seq.frames[0]);
  for (auto _ : state) benchmark::DoNotOptimize(prepare_frame(image, seq.intrinsics, 4));
}

void BM_OdometryLinearizeLevel0(benchmark::State& state, bool joint_weights) {
  const FramePair* pair = shared_pair();
  if (!pair) {
    state.SkipWithError(("shared data absent: " + kSequence).c_str());
    return;
  }
  RgbdProblemOptions po;
  po.joint_weights = joint_weights;  // method joint: one bivariate-t weight per pixel
  RgbdOdometryProblem problem(pair->reference.pyramid.levels[0], pair->current.pyramid.levels[0], po);
  Eigen::VectorXd x = bivo::solvers::se3::to_ambient(*pair->groundtruth_T21);
  for (auto _ : state) {
    // Alternate two poses so the problem's warp cache never short-cuts the work.
    x(0) += 1e-6;
    benchmark::DoNotOptimize(problem.linearize(x, {}));
  }
  state.counters["terms"] = problem.num_terms();
}

}  // namespace

BENCHMARK_CAPTURE(BM_OdometryPair, single, std::string("single"), std::string(""))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_OdometryPair, depth, std::string("depth"), std::string(""))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_OdometryPair, fixed, std::string("fixed"), std::string(""))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_OdometryPair, tykkala, std::string("tykkala"), std::string(""))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_OdometryPair, weighted, std::string("weighted"), std::string(""))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_OdometryPair, bounded, std::string("bounded"), std::string(""))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_OdometryPair, joint, std::string("joint"), std::string(""))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_OdometryPair, scaled, std::string("scaled"), std::string(""))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_OdometryPair, noise_bounded, std::string("noise-bounded"), std::string(""))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_OdometryPair, weighted_lm, std::string("weighted"), std::string("lm"))->Unit(benchmark::kMillisecond);
BENCHMARK(BM_OdometryPrepareFrame)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_OdometryLinearizeLevel0, independent, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_OdometryLinearizeLevel0, joint, true)->Unit(benchmark::kMillisecond);
