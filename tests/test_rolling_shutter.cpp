// Rolling shutter (rolling_shutter.h, TrackerOptions::readout_time): the plane scene's colour
// image read row by row while the camera moves, moved to its timestamp, against the plane as a
// global shutter sees it then (closed form), and a pair of such frames estimated with and
// without the readout time.
#include <cmath>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "odometry/odometry_methods.h"
#include "odometry/rolling_shutter.h"
#include "odometry/synth/defects.h"
#include "odometry/tracker.h"
#include "solvers/error.h"
#include "tests/support/plane_scene.h"

using namespace bivo;
using namespace bivo::odometry;
namespace se3 = bivo::solvers::se3;
using bivo::testing::camera2;
using bivo::testing::camera_at;
using bivo::testing::cm_or_deg;
using bivo::testing::kK;
using bivo::testing::render_plane;
using bivo::testing::render_plane_rows;

namespace {

constexpr double kInterval = 1.0 / 30.0;
constexpr double kReadout = 0.9 * kInterval;  // rows read over 0.9 of the scene's motion

// Its velocity, log(T_21) per second.
const se3::Vector6d kVelocity = se3::log(camera2().inverse()) / kInterval;

// The frame at fraction s: colour read by the rolling shutter (row v at its own time), depth
// taken at the timestamp (the middle row's).
io::RgbdImage rolling_frame(double s) {
  io::RgbdImage im = render_plane_rows([s](int v) { return camera_at(s + row_time(v, 240, kReadout) / kInterval); });
  im.depth = render_plane(camera_at(s)).depth;
  im.timestamp = s * kInterval;
  return im;
}

ImageF image(const std::vector<float>& data) {
  ImageF im;
  im.width = 320;
  im.height = 240;
  im.data = data;
  return im;
}

// Mean absolute intensity difference away from the border.
double mean_difference(const ImageF& a, const ImageF& b) {
  double sum = 0.0;
  int n = 0;
  for (int v = 12; v < a.height - 12; ++v) {
    for (int u = 12; u < a.width - 12; ++u, ++n) sum += std::fabs(double(a.at(u, v)) - b.at(u, v));
  }
  return sum / n;
}

}  // namespace

TEST(RollingShutter, RowTimes) {
  EXPECT_DOUBLE_EQ(row_time(0, 480, 0.024), -0.024 * 479.0 / 960.0);
  EXPECT_DOUBLE_EQ(row_time(479, 480, 0.024), 0.024 * 479.0 / 960.0);
  EXPECT_NEAR(row_time(239, 480, 0.024) + row_time(240, 480, 0.024), 0.0, 1e-15);
  // The renderer's own convention (bivo synth, no exposure): the same time for every row.
  synth::SensorDefects d;
  d.readout_s = 0.024;
  for (int v : {0, 100, 239, 240, 479})
    EXPECT_DOUBLE_EQ(synth::row_sample_times(d, v, 480).at(0), row_time(v, 480, 0.024)) << v;
}

// The image read while the camera moved 0.9 of the scene's 2.1 cm / 0.96 deg, moved to its
// timestamp, is the plane as a global shutter sees it then.
TEST(RollingShutter, PlaneSeenByAGlobalShutter) {
  const io::RgbdImage rolling = rolling_frame(1.0);
  const ImageF truth = image(render_plane(camera_at(1.0)).intensity);
  const ImageF taken = image(rolling.intensity), depth = image(rolling.depth);
  const ImageF moved = global_shutter_intensity(taken, depth, kK, kVelocity, kReadout);
  const double after = mean_difference(moved, truth), before = mean_difference(taken, truth);
  EXPECT_LT(after, 0.05) << "gray levels";  // measured 0.024 (the sines interpolated bilinearly)
  EXPECT_GT(before, 1.0) << "gray levels";  // measured 1.30: the readout matters
  // No readout: the image itself (bilinear interpolation at the pixel centres, to float rounding).
  const ImageF same = global_shutter_intensity(taken, depth, kK, kVelocity, 0.0);
  for (std::size_t i = 0; i < taken.data.size(); ++i) ASSERT_NEAR(same.data[i], taken.data[i], 1e-3) << i;
}

// The per-pixel pass of every instruction set built in and supported here against the scalar
// one, on the frame above and on a fast one (4x the motion, so that rows land far from their
// own) with holes in its depth and a row without any, with one thread and three: equal bit for
// bit, pixel by pixel.
TEST(RollingShutter, EveryInstructionSetMovesTheImageAlike) {
  const io::RgbdImage rolling = rolling_frame(1.0);
  const ImageF taken = image(rolling.intensity);
  ImageF depth = image(rolling.depth);
  for (int v = 0; v < depth.height; v += 7) {
    for (int u = (v * 13) % 17; u < depth.width; u += 17) depth.at(u, v) = 0.0f;  // holes
  }
  for (int u = 0; u < depth.width; ++u) depth.at(u, 5) = 0.0f;  // a row starting without depth
  for (const double speed : {1.0, 4.0}) {
    const ImageF scalar = global_shutter_intensity(taken, depth, kK, speed * kVelocity, kReadout, KernelIsa::kScalar);
    ASSERT_GT(mean_difference(scalar, taken), 0.5 * speed) << "gray levels: the image moved";
    for (const KernelIsa isa : {KernelIsa::kScalar, KernelIsa::kAvx2, KernelIsa::kAvx512Vl, KernelIsa::kAvx512}) {
      if (!kernels_available(isa)) continue;
      for (const int threads : {1, 3}) {  // rows split over threads: the same image
        if (isa == KernelIsa::kScalar && threads == 1) continue;
        SCOPED_TRACE(std::string(to_string(isa)) + ", speed " + std::to_string(speed) + ", " + std::to_string(threads) +
                     " threads");
        const ImageF lanes = global_shutter_intensity(taken, depth, kK, speed * kVelocity, kReadout, isa, threads);
        std::size_t differ = 0;
        for (std::size_t i = 0; i < scalar.data.size(); ++i) differ += lanes.data[i] != scalar.data[i];
        EXPECT_EQ(differ, 0u) << "pixels";
      }
    }
  }
}

// Two rolling-shutter frames: the pair's motion is found when the readout is given, and missed
// (the rows' motion bends the image) when the frames are taken as global-shutter images.
TEST(RollingShutter, PairFoundWithTheReadoutTime) {
  const PreparedFrame reference = prepare_frame(rolling_frame(0.0), kK, 3);
  const PreparedFrame current = prepare_frame(rolling_frame(1.0), kK, 3);
  const Eigen::Isometry3d T_21 = camera2().inverse();
  const auto error_of = [&](const char* method, double readout) {
    TrackerOptions o;
    o.method = method;
    o.levels = 3;
    o.readout_time = readout;
    const PairResult r = estimate_motion(reference, current, Eigen::Isometry3d::Identity(), o);
    EXPECT_TRUE(r.valid);
    return cm_or_deg(r.T_21, T_21);
  };
  for (const char* method : {"single", "joint"}) {
    const double given = error_of(method, kReadout), ignored = error_of(method, 0.0);
    EXPECT_LT(given, 3e-3) << method << " (cm or deg)";    // measured 1.0e-3 single, 4.5e-4 joint
    EXPECT_GT(ignored, 2e-2) << method << " (cm or deg)";  // measured 5.0e-2 single, 3.8e-2 joint
  }
}

// Accelerating motion (the camera at phi(s) = s + s^2 / 2 of the scene's motion at frame time s):
// the velocity at each frame's time, linear through the pair before and this one, is exact for
// it; the pair's own mean velocity is off by half the change over the pair at both frames.
// The pair before is given as track_sequence gives it (PreparedFrame::arrival_velocity).
TEST(RollingShutter, AcceleratingPairWithThePairBefore) {
  const auto phi = [](double s) { return s + 0.5 * s * s; };
  const auto frame = [&](double s) {
    io::RgbdImage im =
        render_plane_rows([&](int v) { return camera_at(phi(s + row_time(v, 240, kReadout) / kInterval)); });
    im.depth = render_plane(camera_at(phi(s))).depth;
    im.timestamp = s * kInterval;
    return prepare_frame(im, kK, 3);
  };
  const PreparedFrame current = frame(1.0);
  PreparedFrame reference = frame(0.0);
  const Eigen::Isometry3d T_21 = camera_at(phi(0.0) - phi(1.0));
  const auto error = [&](int rounds) {
    TrackerOptions o;
    o.method = "joint";
    o.levels = 3;
    o.readout_time = kReadout;
    o.correction_rounds = rounds;
    const PairResult r = estimate_motion(reference, current, Eigen::Isometry3d::Identity(), o);
    EXPECT_TRUE(r.valid);
    return cm_or_deg(r.T_21, T_21);
  };
  const double constant = error(1);
  reference.arrival_velocity = se3::log(camera_at(phi(-1.0) - phi(0.0))) / kInterval;  // the pair before, exact
  reference.arrival_time = -0.5 * kInterval;
  const double linear = error(1);
  // Measured 0.030 and 0.170 (0.197 as global-shutter frames): the first estimate's error
  // carried into the velocities.
  EXPECT_LT(linear, 0.06) << "cm or deg";
  EXPECT_GT(constant, 4.0 * linear) << constant << " vs " << linear << " cm or deg";
  // A second correction, from the velocity the corrected frames gave (TrackerOptions::
  // correction_rounds): closer to the truth.
  const double twice = error(2);
  EXPECT_LT(twice, 0.5 * linear) << twice << " vs " << linear << " cm or deg";
}

// With two threads the two frames of a pair are moved side by side (estimate_motion): the
// same estimate, bit for bit, as one thread's, each correction round.
TEST(RollingShutter, TwoThreadsMoveTheFramesAsOne) {
  const PreparedFrame reference = prepare_frame(rolling_frame(0.0), kK, 3);
  const PreparedFrame current = prepare_frame(rolling_frame(1.0), kK, 3);
  TrackerOptions o;
  o.method = "joint";
  o.levels = 3;
  o.readout_time = kReadout;
  for (const int rounds : {1, 3}) {
    o.correction_rounds = rounds;
    o.problem.threads = 1;
    const PairResult one = estimate_motion(reference, current, Eigen::Isometry3d::Identity(), o);
    o.problem.threads = 2;
    const PairResult two = estimate_motion(reference, current, Eigen::Isometry3d::Identity(), o);
    ASSERT_TRUE(one.valid && two.valid) << rounds;
    EXPECT_EQ(one.T_21.matrix(), two.T_21.matrix()) << rounds;
    EXPECT_LT(cm_or_deg(one.T_21, camera2().inverse()), 3e-3) << rounds;  // the frames were moved
  }
}

TEST(RollingShutter, CorrectionRoundsOneToTenOrTheMethods) {
  for (const std::string& m : method_names()) {
    const Method method = parse_method(m);
    EXPECT_EQ(method_correction_rounds(method, -1), method == Method::kJoint ? 2 : 1) << m;
    EXPECT_EQ(method_correction_rounds(method, 3), 3) << m;  // a request is kept
  }
  TrackerOptions o;
  for (const int good : {-1, 1, 10}) {
    o.correction_rounds = good;
    EXPECT_NO_THROW(validate(o)) << good;
  }
  for (const int bad : {0, -2, 11}) {
    o.correction_rounds = bad;
    EXPECT_THROW(validate(o), Error) << bad;
  }
}

TEST(RollingShutter, WithinOneSecondOrTheSequences) {
  TrackerOptions o;  // -1, the sequence's: test_stated_readout.cpp
  for (const double bad : {-0.001, -2.0, 1.5, std::numeric_limits<double>::quiet_NaN()}) {
    o.readout_time = bad;
    EXPECT_THROW(validate(o), Error) << bad;
  }
}
