// Frames that carry no information for an objective (no valid depth, an image without
// contrast): every method that reads it falls back to the motion prior, says why, and returns a
// finite pose (tracker.h); a method that does not read it still estimates. Depth that fits to
// the last bit leaves a finite pose too.
#include <algorithm>
#include <filesystem>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "odometry/image_statistics.h"
#include "odometry/io/tum_dataset.h"
#include "odometry/odometry_methods.h"
#include "odometry/tracker.h"
#include "solvers/geometry/se3.h"

using namespace bivo;
using namespace bivo::odometry;
using namespace bivo::odometry::io;

namespace {

// A 64x48 frame: an intensity pattern of 50 gray levels, depth(x, y) at each pixel.
template <class Depth>
RgbdImage pattern_frame(const Depth& depth) {
  RgbdImage im;
  im.width = 64;
  im.height = 48;
  for (int y = 0; y < 48; ++y) {
    for (int x = 0; x < 64; ++x) {
      im.intensity.push_back(static_cast<float>((x * 7 + y * 3) % 50));
      im.depth.push_back(depth(x, y));
    }
  }
  return im;
}

// The motion prior the pairs start from: 1 cm and about 1 deg.
Eigen::Isometry3d small_prior() {
  solvers::se3::Vector6d xi;
  xi << 0.01, 0.0, 0.0, 0.0, 0.02, 0.0;
  return solvers::se3::exp(xi);
}

}  // namespace

TEST(FramesWithoutInformation, LevelsWithoutDepthFallBackToTheMotionPrior) {
  const RgbdImage im = pattern_frame([](int, int) { return 0.0f; });  // no valid depth anywhere
  TrackerOptions o;
  o.levels = 3;
  const PreparedFrame a = prepare_frame(im, Intrinsics{}, 3), b = prepare_frame(im, Intrinsics{}, 3);
  const Eigen::Isometry3d prior = small_prior();
  for (const char* method : {"single", "bounded", "fixed"}) {
    o.method = method;
    const PairResult r = estimate_motion(a, b, prior, o);
    EXPECT_FALSE(r.valid) << method;
    EXPECT_TRUE(r.T_21.matrix().allFinite());
    EXPECT_LT((r.T_21.matrix() - prior.matrix()).norm(), 1e-12);
    EXPECT_NE(r.note.find("motion prior"), std::string::npos) << r.note;
    for (const auto& level : r.levels) EXPECT_TRUE(level.skipped);
  }
}

// A black (or saturated) image, as reference or as current image: F_I holds no information, so
// every method that reads it keeps the motion prior instead of a pose it moved for nothing;
// depth alone still estimates.
TEST(FramesWithoutInformation, AnImageWithoutContrastFallsBackToTheMotionPrior) {
  const RgbdImage textured =
      pattern_frame([](int x, int y) { return 1.0f + 0.01f * static_cast<float>(x % 5 + y % 3); });  // a bumpy wall
  RgbdImage black = textured;
  black.intensity.assign(black.intensity.size(), 0.0f);
  for (float& v : black.intensity) v += (&v - black.intensity.data()) % 2 ? 0.9f : 0.0f;  // < 1 gray level
  TrackerOptions o;
  o.levels = 3;
  const PreparedFrame lit = prepare_frame(textured, Intrinsics{}, 3), dark = prepare_frame(black, Intrinsics{}, 3);
  const Eigen::Isometry3d prior = small_prior();
  for (const auto& [reference, current] : {std::pair{&dark, &lit}, std::pair{&lit, &dark}}) {
    for (const std::string& method : method_names()) {
      o.method = method;
      const PairResult r = estimate_motion(*reference, *current, prior, o);
      ASSERT_TRUE(r.T_21.matrix().allFinite()) << method;
      if (method == "depth") {
        EXPECT_TRUE(r.valid) << r.note;
        continue;
      }
      EXPECT_FALSE(r.valid) << method;
      EXPECT_LT((r.T_21.matrix() - prior.matrix()).norm(), 1e-12) << method;
      // weighted's rule has no lambda without the reference's gradients and says so first.
      const bool said = r.note.find("without contrast") != std::string::npos ||
                        (method == "weighted" && r.note.find("lambda undefined") != std::string::npos);
      EXPECT_TRUE(said) << method << ": " << r.note;
      EXPECT_NE(r.note.find("motion prior"), std::string::npos) << method << ": " << r.note;
    }
  }
  EXPECT_FALSE(has_contrast(dark.pyramid.levels[0].intensity));
  EXPECT_TRUE(has_contrast(lit.pyramid.levels[0].intensity));
}

// Real fr1/desk frames whose depth is one flat 1 m: on pair 1 -> 2 r_D falls to ~1e-20 m and
// S_DD below what float inverts (JointWeights.AScaleWithoutAFloatInverseGivesUnitWeights).
// Every method returns a finite pose.
TEST(FramesWithoutInformation, DepthThatFitsToTheLastBitLeavesAFinitePose) {
  const std::string dir = std::string(BIVO_SHARED_DIR) + "/data/tum/rgbd_dataset_freiburg1_desk";
  if (!std::filesystem::exists(dir)) GTEST_SKIP() << "shared data absent: " << dir;
  const TumSequence seq = open_tum_sequence(dir);
  const auto flat = [&](int k) {
    RgbdImage im = load_rgbd_image(seq.frames.at(static_cast<std::size_t>(k)));
    std::fill(im.depth.begin(), im.depth.end(), 1.0f);
    return prepare_frame(std::move(im), seq.intrinsics, 4);
  };
  const PreparedFrame reference = flat(1), current = flat(2);
  for (const std::string& method : method_names()) {
    TrackerOptions o;
    o.method = method;
    PairResult r;
    ASSERT_NO_THROW(r = estimate_motion(reference, current, Eigen::Isometry3d::Identity(), o)) << method;
    EXPECT_TRUE(r.T_21.matrix().allFinite()) << method;
  }
}
