// Cheap guard of the benchmark set's key property (docs/synthetic.md "Benchmark set"): on a
// structure scene, depth-only tracking with the tracker's default parameters follows the
// camera (the full 300-frame check must reach <= 0.01 m/s RPE); on the plane it cannot.
// Short renderings (12 frames, 6 for the plane, of generated hand-held motion at 640x480,
// no data needed) at the far distance, the harder of the two; ground truth is exact.
#include <sys/types.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "odometry/synth/sequence.h"
#include "odometry/tracker.h"
#include "solvers/error.h"

namespace fs = std::filesystem;
namespace synth = bivo::odometry::synth;

namespace {

// RMS over the pairs of the translation error of T_21 against ground truth [m].
double depth_only_rms_pair_error(const std::string& category, int frames, const fs::path& out) {
  synth::SynthOptions o;
  o.category = synth::parse_category(category);
  o.frames = frames;
  o.seed = 5;
  const std::string seq = synth::render_sequence(o, out.string());
  bivo::odometry::TrackerOptions t;  // defaults, as the benchmark check runs them
  t.method = "depth";
  const bivo::odometry::TrackResult r = bivo::odometry::track_sequence(seq, t);
  double sum = 0;
  int n = 0;
  for (const auto& p : r.pairs) {
    if (!p.error) continue;
    sum += p.error->translation_m * p.error->translation_m;
    ++n;
  }
  EXPECT_EQ(n, o.frames - 1) << category;
  return std::sqrt(sum / std::max(n, 1));
}

// Six frames of a textured near scene (seed 3) rendered into a fresh `out`; the sequence.
std::string render_six_near_frames(const fs::path& out) {
  fs::remove_all(out);
  synth::SynthOptions o;
  o.category = synth::parse_category("structure_texture_near");
  o.frames = 6;
  o.seed = 3;
  return synth::render_sequence(o, out.string());
}

}  // namespace

TEST(SynthTracking, DepthAloneTracksTheStructureSceneButNotThePlane) {
  const fs::path out = fs::temp_directory_path() / ("bivo_test_synth_tracking_" + std::to_string(::getpid()));
  fs::remove_all(out);
  const double structure = depth_only_rms_pair_error("structure_notexture_far", 12, out);
  // The control fails by far more than the margin: 6 frames are enough (the test's cost is
  // mostly rendering and PNG writing).
  const double plane = depth_only_rms_pair_error("nostructure_notexture_far", 6, out);
  std::cout << "depth-only RMS per-pair translation error: structure_notexture_far " << structure * 1000
            << " mm, nostructure_notexture_far " << plane * 1000 << " mm\n";
  // This faster generated motion measures 0.90 mm; the 300-frame far benchmark renderings
  // 1.08 mm RMS per pair and 0.0079 m/s RPE against the 0.01 m/s the benchmark requires
  // (docs/synthetic.md), so the bound keeps about that margin. Panels without a floor (one
  // translation unobservable) gave tens of mm.
  EXPECT_LT(structure, 1.2e-3);
  // The plane leaves sliding along it to the motion prior: errors of the size of the motion.
  EXPECT_GT(plane, 10.0 * structure);
  fs::remove_all(out);
}

// Loading the next frame on a thread of its own while a pair is tracked changes no estimate:
// the same trajectory bit for bit as loading between pairs, as two threads (which prepare
// each frame while the pair before it is estimated: sequence_tracking.h), and as three frame
// loaders (frames decoded out of order, delivered in order).
TEST(SynthTracking, LoadingAheadChangesNoEstimate) {
  const fs::path out = fs::temp_directory_path() / ("bivo_test_synth_prefetch_" + std::to_string(::getpid()));
  const std::string seq = render_six_near_frames(out);
  bivo::odometry::TrackerOptions t;
  t.method = "weighted";
  const auto track = [&](bool prefetch, int threads, int loaders) {
    t.prefetch_frames = prefetch;
    t.problem.threads = threads;
    t.load_threads = loaders;
    return bivo::odometry::track_sequence(seq, t);
  };
  const bivo::odometry::TrackResult ahead = track(true, 1, 1), between = track(false, 1, 1), two = track(true, 2, 1),
                                    three_loaders = track(true, 1, 3), both = track(true, 2, 3);
  ASSERT_EQ(ahead.trajectory.size(), 6u);
  for (const auto* other : {&between, &two, &three_loaders, &both}) {
    ASSERT_EQ(other->trajectory.size(), ahead.trajectory.size());
    for (std::size_t k = 0; k < ahead.trajectory.size(); ++k) {
      EXPECT_EQ(other->trajectory[k].T_wc.matrix(), ahead.trajectory[k].T_wc.matrix()) << k;
      EXPECT_EQ(other->trajectory[k].timestamp, ahead.trajectory[k].timestamp) << k;
    }
    for (std::size_t k = 0; k < ahead.pairs.size(); ++k) {
      EXPECT_EQ(other->pairs[k].iterations, ahead.pairs[k].iterations) << k;
      EXPECT_GT(other->pairs[k].cpu_seconds, 0.0) << k;
    }
  }
  // The estimates are good ones: the check above compares working runs.
  for (const auto& p : ahead.pairs) {
    ASSERT_TRUE(p.error);
    EXPECT_LT(p.error->translation_m, 0.01);
  }
  fs::remove_all(out);
}

// --step-extrapolation reaches every level's solve: fewer iterations over the sequence, and
// every pair still within 1 cm of the rendering's exact ground truth.
TEST(SynthTracking, ExtrapolatedStepsTrackWithFewerIterations) {
  const fs::path out = fs::temp_directory_path() / ("bivo_test_synth_extrapolation_" + std::to_string(::getpid()));
  const std::string seq = render_six_near_frames(out);
  bivo::odometry::TrackerOptions t;
  t.method = "weighted";
  const bivo::odometry::TrackResult plain = bivo::odometry::track_sequence(seq, t);
  t.step_extrapolation = 1.9;
  const bivo::odometry::TrackResult extrapolated = bivo::odometry::track_sequence(seq, t);
  ASSERT_EQ(extrapolated.pairs.size(), plain.pairs.size());
  int plain_iterations = 0, extrapolated_iterations = 0;
  for (std::size_t k = 0; k < plain.pairs.size(); ++k) {
    plain_iterations += plain.pairs[k].iterations;
    extrapolated_iterations += extrapolated.pairs[k].iterations;
    ASSERT_TRUE(extrapolated.pairs[k].error);
    EXPECT_LT(extrapolated.pairs[k].error->translation_m, 0.01) << k;
  }
  EXPECT_LT(extrapolated_iterations, plain_iterations);
  fs::remove_all(out);
}

// A frame that fails to load stops the stream after the same pairs with one thread (which
// prepares each frame right before its pair) and with two (which load and prepare it one pair
// ahead, and must still deliver the pair before it first); the error names the file.
TEST(SynthTracking, ABadFrameStopsOneAndTwoThreadsAfterTheSamePairs) {
  const fs::path out = fs::temp_directory_path() / ("bivo_test_synth_bad_frame_" + std::to_string(::getpid()));
  const std::string seq = render_six_near_frames(out);
  // Cut the colour image of frame 4 (rgb.txt lists the frames in order, after its comments).
  std::ifstream list(fs::path(seq) / "rgb.txt");
  std::vector<std::string> files;
  for (std::string line; std::getline(list, line);) {
    if (!line.empty() && line[0] != '#') files.push_back(line.substr(line.find(' ') + 1));
  }
  ASSERT_EQ(files.size(), 6u);
  const fs::path bad = fs::path(seq) / files[4];
  fs::resize_file(bad, fs::file_size(bad) / 2);

  for (const int threads : {1, 2}) {
    for (const int loaders : {1, 3}) {  // three: frame 5 may be decoded before frame 4 fails
      bivo::odometry::TrackerOptions t;
      t.method = "weighted";
      t.problem.threads = threads;
      t.load_threads = loaders;
      std::vector<int> delivered;
      try {
        bivo::odometry::track_sequence(seq, t,
                                       [&](const bivo::odometry::PairResult& p) { delivered.push_back(p.index); });
        ADD_FAILURE() << "no error, threads " << threads << ", loaders " << loaders;
      } catch (const bivo::Error& e) {
        EXPECT_NE(std::string(e.what()).find(files[4]), std::string::npos) << e.what();
      }
      // Pairs 0-1, 1-2 and 2-3; pair 3-4 needs the bad frame.
      EXPECT_EQ(delivered, (std::vector<int>{0, 1, 2})) << "threads " << threads << ", loaders " << loaders;
    }
  }
  fs::remove_all(out);
}
