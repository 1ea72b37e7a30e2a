// CPU milliseconds per frame pair of each odometry method on real fr1/rpy frames, as `bivo run`
// spends them: the current frame's pyramid and statistics plus the coarse-to-fine estimate
// (PNG decoding and undistortion excluded: `bivo run` does both while loading), frames streamed
// in order with the constant-velocity prior, undistorted as `bivo run` undistorts them. Two
// windows of 16 consecutive frames (0-15 and 120-135: 30 pairs), finest level 0 (640x480)
// and 1 (320x240, DVO's default). Counters: median_ms / mean_ms per pair (process CPU time,
// every thread; wall time for the threaded case), it_per_pair (outer iterations).
//
// The file also compiles against the API of commit bfd19e8 (before the float kernels), so
// the same cases run on the old code for paired comparisons (docs/odometry.md "Speed").
#include <time.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "odometry/tracker.h"
#if __has_include("odometry/io/tum_dataset.h")
#include "odometry/io/tum_dataset.h"
namespace data = bivo::odometry::io;
#else
#include "odometry/tum_dataset.h"
namespace data = bivo::odometry;
#endif
#if __has_include("odometry/io/lens_distortion.h")
#include "odometry/io/lens_distortion.h"
#define BIVO_BENCH_UNDISTORT 1
#endif
#if __has_include("odometry/sequence_tracking.h")
#include "odometry/sequence_tracking.h"
#define BIVO_BENCH_STREAM 1
#endif
#if __has_include("odometry/depth_retiming.h")
#define BIVO_BENCH_RETIME 1  // TrackerOptions::retime_depth
#endif
#if __has_include("odometry/rolling_shutter.h")
#define BIVO_BENCH_ROLLING 1  // TrackerOptions::readout_time
#endif
#if __has_include("odometry/kernels/rgbd_kernels.h")
#define BIVO_BENCH_THREADS 1
#define BIVO_PREPARE(image, K, o) prepare_frame(image, K, (o).levels, (o).problem.threads, (o).finest_level)
#else
#define BIVO_PREPARE(image, K, o) prepare_frame(image, K, (o).levels)
#endif

namespace {

using namespace bivo::odometry;

const std::string kRpy = std::string(BIVO_SHARED_DIR) + "/data/tum/rgbd_dataset_freiburg1_rpy";
constexpr int kWindow = 16;
constexpr int kWindowStarts[] = {0, 120};

double cpu_now() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

double wall_now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

struct Frames {
  data::TumSequence sequence;
  std::vector<std::vector<data::RgbdImage>> windows;
};

// Decoded (and undistorted, where the code has it) once; null when the shared data is absent.
const Frames* frames() {
  static std::unique_ptr<Frames> f = []() -> std::unique_ptr<Frames> {
    if (!std::filesystem::exists(kRpy)) return nullptr;
    auto out = std::make_unique<Frames>();
    out->sequence = data::open_tum_sequence(kRpy);
#ifdef BIVO_BENCH_UNDISTORT
    std::optional<data::Undistortion> map;
#endif
    for (int start : kWindowStarts) {
      out->windows.emplace_back();
      for (int k = start; k < start + kWindow; ++k) {
        out->windows.back().push_back(data::load_rgbd_image(out->sequence.frames.at(k)));
#ifdef BIVO_BENCH_UNDISTORT
        data::RgbdImage& image = out->windows.back().back();
        if (!map) map.emplace(out->sequence.intrinsics, out->sequence.distortion, image.width, image.height);
        map->apply(image);
#endif
      }
    }
    return out;
  }();
  return f.get();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n == 0 ? 0.0 : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// The decoded frames, or null after marking the case skipped when the shared data is absent.
const Frames* frames_or_skip(benchmark::State& state) {
  const Frames* f = frames();
  if (!f) state.SkipWithError(("shared data absent: " + kRpy).c_str());
  return f;
}

void report_pairs(benchmark::State& state, const std::vector<double>& per_pair, double iterations, int pairs) {
  state.counters["median_ms"] = median(per_pair);
  double sum = 0;
  for (double v : per_pair) sum += v;
  state.counters["mean_ms"] = per_pair.empty() ? 0.0 : sum / double(per_pair.size());
  state.counters["it_per_pair"] = pairs ? iterations / pairs : 0.0;
}

// fixed_eps > 0: method bounded with that per-unit-weight bound instead of the pi(D) rule.
// extrapolation: TrackerOptions::step_extrapolation (1 = off; -1, the default: the method's own).
// retime: TrackerOptions::retime_depth (fr1's depth is unsynchronized: every pair retimes).
// readout: TrackerOptions::readout_time (every pair also retimes its depth).
void rpy_pairs(benchmark::State& state, const std::string& method, int finest, int threads, double fixed_eps, bool wall,
               double extrapolation, int retime = 0, double readout = 0.0) {
  const Frames* f = frames_or_skip(state);
  if (!f) return;
  TrackerOptions o;
  o.method = method;
  o.finest_level = finest;
  o.step_extrapolation = extrapolation;
  if (fixed_eps > 0.0) o.policy.eps = fixed_eps;
#ifdef BIVO_BENCH_RETIME
  o.retime_depth = retime;
#else
  if (retime != 0) {
    state.SkipWithError("no depth retiming before it existed");
    return;
  }
#endif
#ifdef BIVO_BENCH_ROLLING
  o.readout_time = readout;
#else
  if (readout != 0.0) {
    state.SkipWithError("no rolling-shutter model before it existed");
    return;
  }
#endif
#ifdef BIVO_BENCH_THREADS
  o.problem.threads = threads;
#else
  if (threads != 1) {
    state.SkipWithError("threads need the float kernels");
    return;
  }
#endif
  std::vector<double> per_pair;
  double iterations = 0;
  int pairs = 0;
  for (auto _ : state) {
    for (const auto& window : f->windows) {
      PreparedFrame reference = BIVO_PREPARE(window[0], f->sequence.intrinsics, o);
      Eigen::Isometry3d velocity = Eigen::Isometry3d::Identity();
      for (std::size_t k = 1; k < window.size(); ++k) {
        // As in `bivo run`, a freshly decoded image goes in (moved by the API that takes it by
        // value; the old API copies it inside prepare_frame, as the old `bivo run` did).
        data::RgbdImage image = window[k];
        const double c0 = cpu_now(), w0 = wall_now();
        PreparedFrame current = BIVO_PREPARE(std::move(image), f->sequence.intrinsics, o);
        const PairResult r = estimate_motion(reference, current, velocity, o);
        const double seconds = wall ? wall_now() - w0 : cpu_now() - c0;
        per_pair.push_back(1000.0 * seconds);
        iterations += r.iterations;
        ++pairs;
        if (r.valid) velocity = r.T_21;
        reference = std::move(current);
      }
    }
  }
  report_pairs(state, per_pair, iterations, pairs);
}

void BM_RpyPairs(benchmark::State& state, const std::string& method, int finest, int threads, double fixed_eps,
                 bool wall) {
  rpy_pairs(state, method, finest, threads, fixed_eps, wall, -1.0);
}

#ifdef BIVO_BENCH_STREAM
// Wall ms per pair as track_sequence streams them: each step estimates a pair while the next
// pair's current frame is prepared beside it (sequence_tracking.h); the first pair's time also
// holds its own current frame's preparation. With two threads the preparation overlaps the
// estimate; compare with RpyPairs/weighted_1thread_wall (with one thread, track_sequence
// prepares each frame right before its pair, as BM_RpyPairs does).
void BM_RpyStream(benchmark::State& state, const std::string& method, int finest, int threads) {
  const Frames* f = frames_or_skip(state);
  if (!f) return;
  TrackerOptions o;
  o.method = method;
  o.finest_level = finest;
  o.problem.threads = threads;
  const auto prepare = [&](data::RgbdImage image) { return BIVO_PREPARE(std::move(image), f->sequence.intrinsics, o); };
  std::vector<double> per_pair;
  double iterations = 0;
  int pairs = 0;
  for (auto _ : state) {
    for (const auto& window : f->windows) {
      PreparedFrame reference = prepare(window[0]);
      data::RgbdImage first_current = window[1];
      double lead = wall_now();
      PreparedFrame current = prepare(std::move(first_current));
      lead = wall_now() - lead;
      Eigen::Isometry3d velocity = Eigen::Isometry3d::Identity();
      for (std::size_t k = 1; k < window.size(); ++k) {
        std::optional<data::RgbdImage> next;
        if (k + 1 < window.size()) next = window[k + 1];
        const double w0 = wall_now();
        StreamStep step =
            estimate_motion_preparing_next(reference, current, velocity, o, std::move(next), f->sequence.intrinsics);
        per_pair.push_back(1000.0 * (lead + wall_now() - w0));
        lead = 0.0;
        iterations += step.pair.iterations;
        ++pairs;
        if (step.pair.valid) velocity = step.pair.T_21;
        reference = std::move(current);
        current = std::move(step.next);
      }
    }
  }
  report_pairs(state, per_pair, iterations, pairs);
}
#endif

void register_cases() {
  for (int finest : {0, 1}) {
    const std::string at = finest == 0 ? "/640x480" : "/320x240";
    // joint and robust beside weighted and single: robust's budget is 1.3x weighted's CPU per pair.
    for (const char* m : {"single", "depth", "fixed", "tykkala", "weighted", "bounded", "joint", "robust"}) {
      benchmark::RegisterBenchmark(("RpyPairs/" + std::string(m) + at).c_str(), BM_RpyPairs, std::string(m), finest, 1,
                                   0.0, false)
          ->Unit(benchmark::kMillisecond)
          ->Iterations(1);
    }
    // Crawling steps extrapolated (the cap measured in docs/results/speed.md; off by default).
    for (const char* m : {"single", "weighted", "bounded"}) {
      benchmark::RegisterBenchmark(("RpyPairs/" + std::string(m) + "_extrapolated" + at).c_str(),
                                   [method = std::string(m), finest](benchmark::State& state) {
                                     rpy_pairs(state, method, finest, 1, 0.0, false, 1.9);
                                   })
          ->Unit(benchmark::kMillisecond)
          ->Iterations(1);
    }
    // joint on depth moved to the colour images' times (--retime-depth 1; off by default).
    benchmark::RegisterBenchmark(
        ("RpyPairs/joint_retimed" + at).c_str(),
        [finest](benchmark::State& state) { rpy_pairs(state, "joint", finest, 1, 0.0, false, -1.0, 1); })
        ->Unit(benchmark::kMillisecond)
        ->Iterations(1);
    // joint on colour images moved to their timestamps (--readout-time; off by default), 25 ms.
    benchmark::RegisterBenchmark(
        ("RpyPairs/joint_rolling" + at).c_str(),
        [finest](benchmark::State& state) { rpy_pairs(state, "joint", finest, 1, 0.0, false, -1.0, 0, 0.025); })
        ->Unit(benchmark::kMillisecond)
        ->Iterations(1);
    // Its wall time with one and two threads (the pair's two frames moved side by side).
    for (const int threads : {1, 2}) {
      benchmark::RegisterBenchmark(
          ("RpyPairs/joint_rolling_" + std::string(threads == 1 ? "1thread" : "2threads") + "_wall" + at).c_str(),
          [finest, threads](benchmark::State& state) {
            rpy_pairs(state, "joint", finest, threads, 0.0, true, -1.0, 0, 0.025);
          })
          ->Unit(benchmark::kMillisecond)
          ->Iterations(1);
    }
    // eps = 1e-5 lies below min F_D per unit weight on most pairs: the exact step is
    // infeasible (multiplier inf) on ~2/3 of the steps and minimizes F_D alone there.
    benchmark::RegisterBenchmark(("RpyPairs/bounded_active" + at).c_str(), BM_RpyPairs, std::string("bounded"), finest,
                                 1, 1e-5, false)
        ->Unit(benchmark::kMillisecond)
        ->Iterations(1);
    // eps = 1e-4 lies below F_D per unit weight of the photometric optimum on many pairs but
    // above its minimum: the bound binds with a finite multiplier (~23 % of the steps,
    // infeasible on 3 %).
    benchmark::RegisterBenchmark(("RpyPairs/bounded_binding" + at).c_str(), BM_RpyPairs, std::string("bounded"), finest,
                                 1, 1e-4, false)
        ->Unit(benchmark::kMillisecond)
        ->Iterations(1);
    benchmark::RegisterBenchmark(("RpyPairs/weighted_2threads_wall" + at).c_str(), BM_RpyPairs, std::string("weighted"),
                                 finest, 2, 0.0, true)
        ->Unit(benchmark::kMillisecond)
        ->Iterations(1);
    benchmark::RegisterBenchmark(("RpyPairs/weighted_1thread_wall" + at).c_str(), BM_RpyPairs, std::string("weighted"),
                                 finest, 1, 0.0, true)
        ->Unit(benchmark::kMillisecond)
        ->Iterations(1);
#ifdef BIVO_BENCH_STREAM
    benchmark::RegisterBenchmark(("RpyStream/weighted_2threads_wall" + at).c_str(), BM_RpyStream,
                                 std::string("weighted"), finest, 2)
        ->Unit(benchmark::kMillisecond)
        ->Iterations(1);
#endif
  }
}

const bool registered = (register_cases(), true);

}  // namespace
