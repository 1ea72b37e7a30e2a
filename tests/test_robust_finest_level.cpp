// Method robust's finest level: exact (current-side) gradients from the start, its own
// tolerance and step extrapolation by default. Checked as rules and on a real frame pair, where
// the default run must be bit-identical to the run that asks for the same settings explicitly
// and differ from runs that ask for others (each setting reaches the tracker).
#include <cmath>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "odometry/odometry_methods.h"
#include "odometry/rgbd_problem.h"
#include "odometry/tracker.h"
#include "solvers/error.h"
#include "tests/support/real_pair.h"

using namespace bivo::odometry;
using namespace bivo::odometry::io;

namespace {
bool same(const PairResult& a, const PairResult& b) {
  return a.T_21.matrix() == b.T_21.matrix() && a.iterations == b.iterations;
}
}  // namespace

TEST(RobustFinestLevel, ExtrapolationAutoIsRobustsOwn) {
  EXPECT_EQ(TrackerOptions{}.step_extrapolation, -1.0);
  EXPECT_EQ(method_step_extrapolation(Method::kRobust, -1.0), 1.9);
  // The coarser levels' tolerance (chosen held out): robust's own, joint's own, a request kept.
  EXPECT_EQ(method_joint_tolerance(Method::kRobust, -1.0), 1e-4);
  EXPECT_EQ(method_joint_tolerance(Method::kJoint, -1.0), 1e-3);
  EXPECT_EQ(method_joint_tolerance(Method::kRobust, 1e-5), 1e-5);
  for (const Method m : {Method::kSingle, Method::kWeighted, Method::kJoint, Method::kNoiseBounded}) {
    EXPECT_EQ(method_step_extrapolation(m, -1.0), 1.0) << to_string(m);
  }
  EXPECT_EQ(method_step_extrapolation(Method::kRobust, 1.0), 1.0);  // a request is kept
  EXPECT_EQ(method_step_extrapolation(Method::kSingle, 3.0), 3.0);
  TrackerOptions bad;
  bad.policy.robust_finest_tolerance = -1e-3;
  try {
    validate(bad);
    ADD_FAILURE() << "-1e-3 accepted";
  } catch (const bivo::Error& e) {
    EXPECT_NE(std::string(e.what()).find("robust finest tolerance must be finite and >= 0"), std::string::npos);
  }
  TrackerOptions step;
  step.policy.robust_finest_step_tolerance = -1.0;  // the tracker's step tolerance
  validate(step);
  for (const double v : {-0.5, std::numeric_limits<double>::infinity(), std::nan("")}) {
    step.policy.robust_finest_step_tolerance = v;
    try {
      validate(step);
      ADD_FAILURE() << v << " accepted";
    } catch (const bivo::Error& e) {
      EXPECT_NE(std::string(e.what()).find("robust finest step tolerance must be finite and >= 0, or -1"),
                std::string::npos);
    }
  }
}

TEST(RobustFinestLevel, TheDefaultRunIsTheRunWithRobustsOwnSettings) {
  TrackerOptions o;
  o.method = "robust";
  o.finest_level = 1;
  const bivo::testing::RealPair pair = bivo::testing::fr1_desk_pair(o.levels), pair2 = bivo::testing::fr1_desk_pair(2);
  if (!pair.reference) GTEST_SKIP() << "shared data absent: " << pair.folder;
  const PreparedFrame &ref = *pair.reference, &cur = *pair.current;
  const auto run = [&](const TrackerOptions& m) { return estimate_motion(ref, cur, Eigen::Isometry3d::Identity(), m); };
  const PairResult by_default = run(o);
  TrackerOptions asked = o, no_extrapolation = o, tight = o, inverse = o, tracker_step = o;
  asked.step_extrapolation = 1.9;
  asked.policy.joint_tolerance = 1e-4;  // the coarser levels'
  asked.policy.robust_finest_tolerance = 1e-3;
  asked.policy.robust_finest_step_tolerance = 2e-5;
  tracker_step.policy.robust_finest_step_tolerance = 1e-2;  // the first step ends the finest level
  no_extrapolation.step_extrapolation = 1.0;
  tight.policy.robust_finest_tolerance = 1e-5;
  inverse.problem.jacobian = JacobianKind::kInverse;  // at every level, then the exact finish
  EXPECT_TRUE(same(by_default, run(asked)));
  EXPECT_FALSE(same(by_default, run(no_extrapolation)));
  const PairResult tight_run = run(tight);
  EXPECT_FALSE(same(by_default, tight_run));
  EXPECT_GT(tight_run.levels.back().iterations, by_default.levels.back().iterations);
  EXPECT_FALSE(same(by_default, run(inverse)));
  const PairResult shorter = run(tracker_step);
  EXPECT_FALSE(same(by_default, shorter));
  EXPECT_LT(shorter.levels.back().iterations, by_default.levels.back().iterations);
  // The finest step tolerance is robust's alone: single ignores it.
  TrackerOptions single = o, single_step = o;
  single.method = single_step.method = "single";
  single_step.policy.robust_finest_step_tolerance = 1e-9;
  EXPECT_TRUE(same(run(single), run(single_step)));
  // The finest level alone: auto is the forward Jacobian there.
  TrackerOptions one_level = o, one_level_forward = o;
  one_level.levels = one_level_forward.levels = 2;
  one_level_forward.problem.jacobian = JacobianKind::kForward;
  const auto run2 = [&](const TrackerOptions& m) {
    return estimate_motion(*pair2.reference, *pair2.current, Eigen::Isometry3d::Identity(), m);
  };
  EXPECT_TRUE(same(run2(one_level), run2(one_level_forward)));
}
