// Milliseconds per frame pair of each odometry method at 640x480 on real TUM frames
// (fr1/desk frames 0 -> 1, 4 pyramid levels, identity start), the building blocks (frame
// preparation, one level-0 linearization and evaluation per instruction set and thread
// count), a warm-started 32-point Pareto sweep against one solve of the same pair, and the
// memory stream rate that bounds the per-pixel passes from below (docs/odometry.md "Speed"),
// and a frame's images moved to its timestamp (--retime-depth, --readout-time).
// Per-method figures on fr1/rpy sequences: bench_odometry_pairs.cpp.
#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "odometry/reference_terms.h"
#if __has_include("odometry/rolling_shutter.h")
#include "odometry/rolling_shutter.h"
#endif
#include "odometry/tracker.h"
#include "solvers/geometry/se3.h"
#include "solvers/pareto.h"

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

#define BIVO_NEED_PAIR(pair)                                           \
  const FramePair* pair = shared_pair();                               \
  if (!pair) {                                                         \
    state.SkipWithError(("shared data absent: " + kSequence).c_str()); \
    return;                                                            \
  }

// Benchmark argument -> kernels: 0 scalar, 1 avx2, 2 avx512vl, 3 avx512 (sixteen lanes).
KernelIsa isa_of(std::int64_t arg) {
  return arg == 3   ? KernelIsa::kAvx512
         : arg == 2 ? KernelIsa::kAvx512Vl
         : arg == 1 ? KernelIsa::kAvx2
                    : KernelIsa::kScalar;
}

void BM_OdometryPair(benchmark::State& state, const std::string& method, const std::string& backend) {
  BIVO_NEED_PAIR(pair);
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
  const int threads = static_cast<int>(state.range(0));
  const bool statistics = state.range(1) != 0;  // weighted and bounded read them
  for (auto _ : state) benchmark::DoNotOptimize(prepare_frame(image, seq.intrinsics, 4, threads, 0, statistics));
}

#if __has_include("odometry/rolling_shutter.h")
// One frame's full-resolution images moved to its timestamp (a pair's correction does two):
// depth retimed (retime = 1) and/or colour from a 25 ms rolling shutter (rolling = 1), at a
// rotation of 6 deg and 4 cm per 33 ms frame (fr1/rpy's fastest pairs).
void BM_OdometryFrameAtTimestamp(benchmark::State& state) {
  BIVO_NEED_PAIR(pair);
  const bool retime = state.range(0) != 0;
  const double readout = state.range(1) != 0 ? 0.025 : 0.0;
  bivo::solvers::se3::Vector6d xi;
  xi << 0.03, -0.02, 0.02, 0.06, 0.08, 0.04;  // log(T_21): |w| = 0.108 rad, |v| = 4.1 cm
  const bivo::solvers::se3::Vector6d velocity = xi * 30.0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(pyramid_at_timestamp(pair->reference.pyramid, velocity, retime, readout));
  }
}
BENCHMARK(BM_OdometryFrameAtTimestamp)
    ->ArgsProduct({{0, 1}, {0, 1}})
    ->ArgNames({"retime", "rolling"})
    ->Unit(benchmark::kMillisecond);
#endif

// Undistorting one loaded fr1 frame with its sequence's map (part of loading, not of a pair).
void BM_OdometryUndistortFrame(benchmark::State& state) {
  if (!std::filesystem::exists(kSequence)) {
    state.SkipWithError(("shared data absent: " + kSequence).c_str());
    return;
  }
  const TumSequence seq = open_tum_sequence(kSequence);
  RgbdImage image = load_rgbd_image(seq.frames[0]);
  const Undistortion map(seq.intrinsics, seq.distortion, image.width, image.height);
  for (auto _ : state) {  // the same work whatever the content: the frame is undistorted again
    map.apply(image);
    benchmark::DoNotOptimize(image.depth.data());
  }
}

// One level-0 linearization (warp, weights, normal equations) with the given kernels and
// threads; joint = 1: method joint's weight stage (one bivariate-t weight per pixel).
void BM_OdometryLinearizeLevel0(benchmark::State& state) {
  BIVO_NEED_PAIR(pair);
  const KernelIsa isa = isa_of(state.range(0));
  if (!kernels_available(isa)) {
    state.SkipWithError("kernels not available on this CPU / build");
    return;
  }
  RgbdProblemOptions po;
  po.threads = static_cast<int>(state.range(1));
  po.joint_weights = state.range(2) != 0;
  RgbdOdometryProblem problem(pair->reference.pyramid.levels[0], pair->current.pyramid.levels[0], po);
  problem.set_kernel_isa(isa);
  Eigen::VectorXd x = bivo::solvers::se3::to_ambient(*pair->groundtruth_T21);
  for (auto _ : state) {
    x(0) += 1e-6;  // a new pose each time: no cached warp
    benchmark::DoNotOptimize(problem.linearize(x, {}));
  }
  state.counters["terms"] = problem.num_terms();
  state.SetLabel(to_string(isa));
}

// The reference-side terms of level 0 (3-D points and intensities of the pixels with usable
// depth), built once per pair and level by every problem ("reference" in `bivo profile`).
void BM_OdometryReferenceTerms(benchmark::State& state) {
  BIVO_NEED_PAIR(pair);
  const int threads = static_cast<int>(state.range(0));
  const bool gradients = state.range(1) != 0;
  std::size_t terms = 0;
  for (auto _ : state) {
    const ReferenceTerms t = make_reference_terms(pair->reference.pyramid.levels[0], 0.1, 10.0, gradients, threads);
    terms = t.count;
    benchmark::DoNotOptimize(t.x.data());
  }
  state.counters["terms"] = static_cast<double>(terms);
}

// One evaluate() at a new pose: the warp with F summed under the stored weights, at level 0
// or a coarser level (level 2's working set fits the L2 cache: equal ns per term at both
// levels says the warp is bound by its instructions, not by memory). store 0: evaluate_only(),
// the same sums without writing the residuals and gradients a linearization would reuse.
void BM_OdometryEvaluateLevel0(benchmark::State& state) {
  BIVO_NEED_PAIR(pair);
  const KernelIsa isa = isa_of(state.range(0));
  if (!kernels_available(isa)) {
    state.SkipWithError("kernels not available on this CPU / build");
    return;
  }
  const auto level = static_cast<std::size_t>(state.range(1));
  RgbdOdometryProblem problem(pair->reference.pyramid.levels[level], pair->current.pyramid.levels[level]);
  problem.set_kernel_isa(isa);
  state.SetLabel(to_string(isa));
  state.counters["ns_per_term"] = benchmark::Counter(
      problem.num_terms(), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  Eigen::VectorXd x = bivo::solvers::se3::to_ambient(*pair->groundtruth_T21);
  problem.linearize(x, {});
  for (auto _ : state) {
    x(0) += 1e-6;
    benchmark::DoNotOptimize(state.range(2) != 0 ? problem.evaluate(x) : problem.evaluate_only(x));
  }
}

// A 32-point lambda sweep at one level (range(0)), warm-started from one method's estimate
// of the same pair, against that estimate (one solve): counter sweep_over_solve (CPU time).
// range(1) = 0: from the weighted method's estimate; 1: from single's, as `bivo pareto`
// starts its sweeps (experiments/pareto_study.cpp).
void BM_ParetoSweep32(benchmark::State& state) {
  BIVO_NEED_PAIR(pair);
  const int level = static_cast<int>(state.range(0));
  TrackerOptions o;
  o.finest_level = level;
  if (state.range(1) == 1) o.method = "single";
  state.SetLabel("from " + o.method);
  double solve_s = 0, sweep_s = 0;
  int solves = 0, iterations = 0;
  bivo::solvers::PhaseProfile phases;  // the sweeps' own phases
  for (auto _ : state) {
    const double t0 = process_cpu_seconds();  // CPU time: the machine is shared
    const PairResult r = estimate_motion(pair->reference, pair->current, Eigen::Isometry3d::Identity(), o);
    const double t1 = process_cpu_seconds();
    auto problem = pair->problem(level, o);
    bivo::solvers::ParetoOptions po;
    po.points = 32;
    po.lambda_min = 1.0;
    po.lambda_max = 1e7;
    po.solver.max_iterations = o.max_iterations;
    po.solver.step_tolerance = o.step_tolerance;
    po.solver.relative_decrease_tolerance = o.relative_decrease_tolerance;
    po.solver.step_measure = [&problem](const Eigen::VectorXd& x, const Eigen::VectorXd& d) {
      return problem->pixel_motion(x, d);
    };
    po.solver.step_measure_tolerance = o.pixel_motion_tolerance;
    po.solver.profile = &phases;
    const auto front = bivo::solvers::sweep_lambda(*problem, bivo::solvers::se3::to_ambient(r.T_21), po);
    const double t2 = process_cpu_seconds();
    benchmark::DoNotOptimize(front.points.size());
    iterations = 0;
    for (const auto& point : front.all) iterations += point.iterations;
    solve_s += t1 - t0;
    sweep_s += t2 - t1;
    ++solves;
  }
  state.counters["solve_ms"] = 1000.0 * solve_s / solves;
  state.counters["sweep_ms"] = 1000.0 * sweep_s / solves;
  state.counters["sweep_over_solve"] = sweep_s / solve_s;
  state.counters["sweep_iterations"] = iterations;  // outer iterations of the 32 points
  for (const auto& [phase, seconds] : phases.all())
    state.counters["sweep_" + phase + "_ms"] = 1000.0 * seconds / solves;
}

// Reading the level-0 working set (~14 MB: reference terms, residual, gradient and weight
// buffers, the interleaved current image) once: the floor of one per-pixel pass.
void BM_OdometryStreamFloor(benchmark::State& state) {
  std::vector<float> buffer(static_cast<std::size_t>(state.range(0)) << 18, 1.0f);  // range(0) MB
  for (auto _ : state) {
    float s0 = 0, s1 = 0, s2 = 0, s3 = 0, s4 = 0, s5 = 0, s6 = 0, s7 = 0;
    for (std::size_t i = 0; i < buffer.size(); i += 8) {
      s0 += buffer[i];
      s1 += buffer[i + 1];
      s2 += buffer[i + 2];
      s3 += buffer[i + 3];
      s4 += buffer[i + 4];
      s5 += buffer[i + 5];
      s6 += buffer[i + 6];
      s7 += buffer[i + 7];
    }
    benchmark::DoNotOptimize(s0 + s1 + s2 + s3 + s4 + s5 + s6 + s7);
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(buffer.size() * 4));
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
BENCHMARK_CAPTURE(BM_OdometryPair, noise_bounded, std::string("noise-bounded"), std::string(""))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_OdometryPair, weighted_lm, std::string("weighted"), std::string("lm"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_OdometryPrepareFrame)
    ->ArgNames({"threads", "statistics"})
    ->Args({1, 0})
    ->Args({1, 1})
    ->Args({2, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_OdometryLinearizeLevel0)
    ->ArgNames({"isa", "threads", "joint"})  // isa: 0 scalar, 1 avx2, 2 avx512vl, 3 avx512
    ->Args({0, 1, 0})
    ->Args({1, 1, 0})
    ->Args({2, 1, 0})
    ->Args({3, 1, 0})
    ->Args({1, 2, 0})
    ->Args({3, 2, 0})
    ->Args({1, 1, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_OdometryEvaluateLevel0)
    ->ArgNames({"isa", "level", "store"})
    ->Args({1, 0, 1})
    ->Args({2, 0, 1})
    ->Args({3, 0, 1})
    ->Args({3, 0, 0})
    ->Args({1, 2, 1})
    ->Args({2, 2, 1})
    ->Args({3, 2, 1})
    ->Args({3, 2, 0})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_OdometryReferenceTerms)
    ->ArgNames({"threads", "gradients"})
    ->Args({1, 0})
    ->Args({2, 0})
    ->Args({1, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_OdometryUndistortFrame)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ParetoSweep32)->ArgsProduct({{0, 1}, {0, 1}})->ArgNames({"level", "start"})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_OdometryStreamFloor)->Arg(14)->Arg(64)->Unit(benchmark::kMillisecond);
