// TrackerOptions::retry_from_rest (estimate_motion_from_prior): a pair that no level could
// solve from its motion prior is solved again from rest, on the procedural plane of
// tests/support/plane_scene.h (no data needed).
#include <string>

#include <gtest/gtest.h>

#include "odometry/rgbd_problem.h"
#include "odometry/tracker.h"
#include "solvers/geometry/se3.h"
#include "tests/support/plane_scene.h"
#include "tests/test_support.h"

using namespace bivo::odometry;
using bivo::testing::error_of;

// A prior under which no reference point lands in the current image (3 m sideways) leaves
// every level unsolved. With retry_from_rest (the default) the pair is estimated again from
// the identity: the result is that estimate to the bit, the procedural plane's true motion to
// 1 mm / 0.05 deg, and the iterations count both solves; without it the prior stands.
TEST(RetryFromRest, APairLostAtItsPriorIsSolvedAgainFromRest) {
  const PreparedFrame a =
      prepare_frame(bivo::testing::render_plane(Eigen::Isometry3d::Identity()), bivo::testing::kK, 3);
  const PreparedFrame b = prepare_frame(bivo::testing::render_plane(bivo::testing::camera2()), bivo::testing::kK, 3);
  const Eigen::Isometry3d truth = bivo::testing::camera2().inverse();
  Eigen::Isometry3d lost = Eigen::Isometry3d::Identity();
  lost.translation() = Eigen::Vector3d(3.0, 0.0, 0.0);
  TrackerOptions o;
  o.levels = 3;
  EXPECT_EQ(o.retry_from_rest, 1);
  for (const char* method : {"single", "joint", "noise-bounded"}) {
    o.method = method;
    o.retry_from_rest = 0;
    const PairResult at_prior = estimate_motion_from_prior(a, b, lost, o);
    EXPECT_FALSE(at_prior.valid) << method;
    EXPECT_EQ(at_prior.T_21.matrix(), lost.matrix()) << method;
    o.retry_from_rest = 1;
    const PairResult from_rest = estimate_motion(a, b, Eigen::Isometry3d::Identity(), o);
    const PairResult retried = estimate_motion_from_prior(a, b, lost, o);
    ASSERT_TRUE(retried.valid) << method << ": " << retried.note;
    EXPECT_EQ(retried.T_21.matrix(), from_rest.T_21.matrix()) << method;
    EXPECT_EQ(retried.iterations, from_rest.iterations + at_prior.iterations) << method;
    EXPECT_NE(retried.note.find("solved from rest"), std::string::npos) << retried.note;
    const io::PoseError e = io::pose_error(retried.T_21, truth);
    EXPECT_LT(e.translation_m, 1e-3) << method;
    EXPECT_LT(e.rotation_deg, 0.05) << method;
    // From the identity itself nothing is retried.
    EXPECT_EQ(estimate_motion_from_prior(a, b, Eigen::Isometry3d::Identity(), o).T_21.matrix(),
              from_rest.T_21.matrix());
  }
  for (int bad : {-1, 2}) {
    o.retry_from_rest = bad;
    const std::string msg = error_of([&] { validate(o); });
    EXPECT_NE(msg.find("retry from rest must be 0 or 1"), std::string::npos) << msg;
  }
}

namespace {

struct Alignment {
  double valid_fraction, sigma;  // of r_I at the finest level, t-distribution scale
};

Alignment alignment_at(const PreparedFrame& a, const PreparedFrame& b, const Eigen::Isometry3d& T) {
  RgbdOdometryProblem p(a.pyramid.levels[0], b.pyramid.levels[0]);
  p.objectives_at(bivo::solvers::se3::to_ambient(T));
  return {double(p.last_stats().valid_intensity) / p.num_terms(), p.last_stats().sigma_intensity};
}

}  // namespace

// The solve from rest can end where more terms stay in view than at the truth (here: one
// Gauss-Newton step per level short of a 0.25 m sideways motion) and pass the valid-fraction
// test the truth fails. It replaces the prior only when it aligns the pair better (the scale
// of r_I); a prior at the true motion, lost for its valid fraction alone, stands bit for bit.
TEST(RetryFromRest, ARetryThatAlignsWorseThanThePriorLeavesThePrior) {
  Eigen::Isometry3d T_wc2 = Eigen::Isometry3d::Identity();
  T_wc2.translation() = Eigen::Vector3d(0.25, 0.0, 0.0);
  const PreparedFrame a =
      prepare_frame(bivo::testing::render_plane(Eigen::Isometry3d::Identity()), bivo::testing::kK, 3);
  const PreparedFrame b = prepare_frame(bivo::testing::render_plane(T_wc2), bivo::testing::kK, 3);
  const Eigen::Isometry3d truth = T_wc2.inverse();
  TrackerOptions o;
  o.levels = 3;
  o.method = "single";
  o.max_iterations = 1;
  o.problem.min_valid_fraction = 0.0;
  const PairResult short_of_it = estimate_motion(a, b, Eigen::Isometry3d::Identity(), o);
  ASSERT_TRUE(short_of_it.valid) << short_of_it.note;
  const Alignment at_truth = alignment_at(a, b, truth), at_retry = alignment_at(a, b, short_of_it.T_21);
  ASSERT_GT(at_retry.valid_fraction, at_truth.valid_fraction + 0.02);
  ASSERT_GT(at_retry.sigma, 2.0 * at_truth.sigma);
  o.problem.min_valid_fraction = 0.5 * (at_truth.valid_fraction + at_retry.valid_fraction);
  const PairResult kept = estimate_motion_from_prior(a, b, truth, o);
  EXPECT_FALSE(kept.valid);
  EXPECT_EQ(kept.T_21.matrix(), truth.matrix());
  EXPECT_NE(kept.note.find("from rest: residual scale"), std::string::npos) << kept.note;
  // The same retry replaces a prior that aligns worse still (twice the motion).
  Eigen::Isometry3d beyond = truth;
  beyond.translation() *= 2.0;
  ASSERT_FALSE(estimate_motion(a, b, beyond, o).valid);
  ASSERT_GT(alignment_at(a, b, beyond).sigma, at_retry.sigma);
  const PairResult replaced = estimate_motion_from_prior(a, b, beyond, o);
  ASSERT_TRUE(replaced.valid) << replaced.note;
  EXPECT_EQ(replaced.T_21.matrix(), short_of_it.T_21.matrix());
}
