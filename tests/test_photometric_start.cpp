// The photometric start's "auto" (PolicyParameters::photometric_start_levels = -1): each
// method's own number of levels, checked as a rule and on a real frame pair, where the default
// run must be bit-identical to the run that asks for that number explicitly.
#include <string>
#include <tuple>

#include <gtest/gtest.h>

#include "odometry/odometry_methods.h"
#include "odometry/tracker.h"
#include "solvers/error.h"
#include "tests/support/real_pair.h"

using namespace bivo::odometry;
using namespace bivo::odometry::io;

TEST(PhotometricStart, AutoIsTwoLevelsForJointAndOneForRobust) {
  EXPECT_EQ(PolicyParameters{}.photometric_start_levels, -1);
  EXPECT_EQ(method_photometric_start_levels(Method::kJoint, -1), 3);
  EXPECT_EQ(method_photometric_start_levels(Method::kRobust, -1), 1);
  EXPECT_EQ(method_photometric_start_levels(Method::kJoint, 0), 0);  // a request is kept
  EXPECT_EQ(method_photometric_start_levels(Method::kRobust, 3), 3);
  TrackerOptions bad;
  bad.policy.photometric_start_levels = -2;
  try {
    validate(bad);
    ADD_FAILURE() << "-2 accepted";
  } catch (const bivo::Error& e) {
    EXPECT_NE(std::string(e.what()).find("photometric start levels must be >= 0, or -1"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("got -2"), std::string::npos);
  }
}

TEST(PhotometricStart, TheDefaultRunIsTheRunWithTheMethodsOwnLevels) {
  TrackerOptions o;
  o.finest_level = 1;
  const bivo::testing::RealPair pair = bivo::testing::fr1_desk_pair(o.levels);
  if (!pair.reference) GTEST_SKIP() << "shared data absent: " << pair.folder;
  const PreparedFrame &ref = *pair.reference, &cur = *pair.current;
  const auto run = [&](const std::string& method, int levels) {
    TrackerOptions m = o;
    m.method = method;
    m.policy.photometric_start_levels = levels;
    return estimate_motion(ref, cur, Eigen::Isometry3d::Identity(), m);
  };
  for (const auto& [method, own, other] : {std::tuple<std::string, int, int>{"joint", 3, 1}, {"robust", 1, 2}}) {
    const PairResult by_default = run(method, -1), asked = run(method, own), not_own = run(method, other);
    EXPECT_TRUE(by_default.T_21.matrix() == asked.T_21.matrix()) << method;
    EXPECT_EQ(by_default.iterations, asked.iterations) << method;
    // The count reaches the tracker: another one solves the pair along another path.
    EXPECT_FALSE(by_default.T_21.matrix() == not_own.T_21.matrix()) << method;
  }
}
