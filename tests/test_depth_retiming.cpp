// Unsynchronized colour and depth (depth_retiming.h, TrackerOptions::retime_depth): the
// retimed depth of the plane scene against the plane seen from the colour camera's pose
// (closed form), the constant-velocity pose against its definition, and a pair whose depth
// images were taken at other poses than its colour images.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "odometry/depth_retiming.h"
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

namespace {

ImageF depth_of(const io::RgbdImage& im) {
  ImageF d;
  d.width = im.width;
  d.height = im.height;
  d.data = im.depth;
  return d;
}

struct Difference {
  double largest = 0.0, mean = 0.0;  // relative depth difference
  int compared = 0;                  // pixels valid in both, away from the border
};

Difference difference(const ImageF& a, const ImageF& b) {
  Difference d;
  for (int v = 10; v < a.height - 10; ++v) {
    for (int u = 10; u < a.width - 10; ++u) {
      if (!(a.at(u, v) > 0.0f && b.at(u, v) > 0.0f)) continue;
      const double e = std::fabs(double(a.at(u, v)) - b.at(u, v)) / b.at(u, v);
      d.largest = std::max(d.largest, e);
      d.mean += e;
      ++d.compared;
    }
  }
  d.mean /= std::max(d.compared, 1);
  return d;
}

}  // namespace

// The plane seen from a camera 3.1 cm / 1.4 deg away, moved to the colour camera at the
// origin, is the plane as the colour camera sees it.
TEST(DepthRetiming, PlaneSeenFromTheColourCamera) {
  const Eigen::Isometry3d depth_pose = camera_at(1.5);
  const ImageF taken = depth_of(render_plane(depth_pose));
  const ImageF truth = depth_of(render_plane(Eigen::Isometry3d::Identity()));
  const ImageF retimed = retime_depth(taken, kK, depth_pose);
  const Difference moved = difference(retimed, truth), as_taken = difference(taken, truth);
  EXPECT_LT(moved.mean, 5e-5);       // measured 3.0e-5 (1.7e-4 with the point's own depth, no slope)
  EXPECT_LT(moved.largest, 1e-3);    // beside a depth hole: no slope, the depth half a pixel away
  EXPECT_GT(moved.compared, 60000);  // of 300 x 220, less the depth holes and where the views differ
  EXPECT_GT(as_taken.mean, 3e-3);    // the delay matters
  // No motion: the image itself, holes included.
  const ImageF same = retime_depth(taken, kK, Eigen::Isometry3d::Identity());
  for (std::size_t i = 0; i < taken.data.size(); ++i) ASSERT_NEAR(same.data[i], taken.data[i], 1e-6) << i;
}

// The splat of every instruction set built in and supported here against the scalar one, at
// the pose above and at 4x its motion, with holes in the depth: equal bit for bit.
TEST(DepthRetiming, EveryInstructionSetMovesTheDepthAlike) {
  ImageF taken = depth_of(render_plane(camera_at(1.5)));
  for (int v = 0; v < taken.height; v += 5) {
    for (int u = (v * 7) % 11; u < taken.width; u += 11) taken.at(u, v) = 0.0f;  // holes
  }
  for (const double speed : {1.0, 4.0}) {
    const Eigen::Isometry3d pose = pose_after_delay(se3::log(camera_at(1.5)) * speed, -1.0);
    const ImageF scalar = retime_depth(taken, kK, pose, KernelIsa::kScalar);
    ASSERT_GT(difference(scalar, taken).mean, 3e-3 * speed) << "the depth moved";
    for (const KernelIsa isa : {KernelIsa::kAvx2, KernelIsa::kAvx512Vl, KernelIsa::kAvx512}) {
      if (!kernels_available(isa)) continue;
      SCOPED_TRACE(std::string(to_string(isa)) + ", speed " + std::to_string(speed));
      const ImageF lanes = retime_depth(taken, kK, pose, isa);
      std::size_t differ = 0;
      for (std::size_t i = 0; i < scalar.data.size(); ++i) differ += lanes.data[i] != scalar.data[i];
      EXPECT_EQ(differ, 0u) << "pixels";
    }
  }
}

TEST(DepthRetiming, ConstantVelocityPose) {
  const Eigen::Isometry3d T_21 = camera2().inverse();
  const double interval = 1.0 / 30.0;
  const se3::Vector6d velocity = se3::log(T_21) / interval;
  EXPECT_TRUE(pose_after_delay(velocity, 0.0).isApprox(Eigen::Isometry3d::Identity(), 1e-12));
  EXPECT_TRUE(pose_after_delay(velocity, interval).isApprox(camera2(), 1e-12));
  const Eigen::Isometry3d half = pose_after_delay(velocity, 0.5 * interval);
  EXPECT_TRUE((half * half).isApprox(camera2(), 1e-12));
  EXPECT_TRUE(pose_after_delay(velocity, -0.25 * interval).isApprox(camera_at(-0.25), 1e-12));
}

// Colour at the start and end of the plane scene's motion, each depth image 0.4 of the motion
// later (TUM freiburg1's unsynchronized sensor): joint finds the motion when it retimes the depth
// and is pulled away (30x farther) when it takes the depth as synchronized. Synchronized frames
// are estimated once, as without the option.
TEST(DepthRetiming, JointFindsTheMotionOnUnsynchronizedDepth) {
  const double interval = 1.0 / 30.0, lag = 0.4;
  const auto frame = [&](double s, double depth_lag) {
    io::RgbdImage im = render_plane(camera_at(s));
    im.depth = render_plane(camera_at(s + depth_lag)).depth;
    im.timestamp = s * interval;
    im.depth_delay = depth_lag * interval;
    return prepare_frame(im, kK, 3);
  };
  const PreparedFrame reference = frame(0.0, lag), current = frame(1.0, lag);
  const Eigen::Isometry3d T_21 = camera2().inverse();
  const auto error_of = [&](int retime, const PreparedFrame& a, const PreparedFrame& b) {
    TrackerOptions o;
    o.method = "joint";
    o.levels = 3;
    o.retime_depth = retime;
    const PairResult r = estimate_motion(a, b, Eigen::Isometry3d::Identity(), o);
    EXPECT_TRUE(r.valid);
    return cm_or_deg(r.T_21, T_21);
  };
  const double retimed = error_of(1, reference, current), taken = error_of(0, reference, current);
  EXPECT_LT(retimed, 1e-3) << "cm or deg";  // measured 1.7e-4
  EXPECT_GT(taken, 3e-3) << "cm or deg";    // measured 5.7e-3: the depth pulls the plane's 3 dof
  const PreparedFrame synced_reference = frame(0.0, 0.0), synced_current = frame(1.0, 0.0);
  EXPECT_EQ(error_of(1, synced_reference, synced_current), error_of(0, synced_reference, synced_current));
}

TEST(DepthRetiming, OffByDefaultAndZeroOrOne) {
  TrackerOptions o;
  EXPECT_EQ(o.retime_depth, 0);
  for (const int bad : {-1, 2}) {
    o.retime_depth = bad;
    EXPECT_THROW(validate(o), Error) << bad;
  }
}
