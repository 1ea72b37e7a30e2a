// Hand-held motion generator (target speeds, smoothness, determinism) and trajectory
// resampling / re-anchoring against direct computations.
#include <cmath>

#include <gtest/gtest.h>

#include "odometry/synth/motion.h"
#include "solvers/error.h"
#include "solvers/geometry/se3.h"

namespace synth = bivo::odometry::synth;
namespace se3 = bivo::solvers::se3;
using bivo::odometry::io::Trajectory;

TEST(SynthMotion, HandheldMotionHasTheTargetMeanSpeeds) {
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    synth::HandheldMotionOptions o;
    o.seed = seed;
    o.duration_s = 6.0;
    o.mean_linear_speed_mps = 0.3;
    o.mean_angular_speed_dps = 20.0;
    const Trajectory t = synth::generate_handheld_motion(o);
    ASSERT_EQ(t.size(), 601u);
    EXPECT_NEAR(t[1].timestamp - t[0].timestamp, 0.01, 1e-12);
    const synth::MotionSpeeds s = synth::mean_speeds(t);
    EXPECT_NEAR(s.linear_mps, 0.3, 0.003) << "seed " << seed;
    EXPECT_NEAR(s.angular_rps * 180 / M_PI, 20.0, 0.2) << "seed " << seed;
  }
}

TEST(SynthMotion, HandheldMotionIsSmoothAndBounded) {
  // Hand-held: accelerations of a few m/s^2 at most (no jumps), excursions of decimetres.
  synth::HandheldMotionOptions o;
  o.seed = 5;
  o.duration_s = 8.0;
  const Trajectory t = synth::generate_handheld_motion(o);
  const double dt = 1.0 / o.rate_hz;
  double max_acc = 0, max_excursion = 0, max_speed = 0;
  for (std::size_t k = 1; k + 1 < t.size(); ++k) {
    const Eigen::Vector3d a =
        (t[k + 1].T_wc.translation() - 2 * t[k].T_wc.translation() + t[k - 1].T_wc.translation()) / (dt * dt);
    max_acc = std::max(max_acc, a.norm());
    max_speed = std::max(max_speed, (t[k + 1].T_wc.translation() - t[k].T_wc.translation()).norm() / dt);
    max_excursion = std::max(max_excursion, (t[k].T_wc.translation() - t[0].T_wc.translation()).norm());
  }
  EXPECT_LT(max_acc, 6.0);
  EXPECT_LT(max_speed, 1.0);
  EXPECT_GT(max_excursion, 0.1);
  EXPECT_LT(max_excursion, 1.5);
}

TEST(SynthMotion, SameSeedSameMotionOtherSeedOtherMotion) {
  synth::HandheldMotionOptions o;
  o.seed = 9;
  const Trajectory a = synth::generate_handheld_motion(o), b = synth::generate_handheld_motion(o);
  o.seed = 10;
  const Trajectory c = synth::generate_handheld_motion(o);
  ASSERT_EQ(a.size(), b.size());
  double diff_ab = 0, diff_ac = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    diff_ab = std::max(diff_ab, (a[k].T_wc.matrix() - b[k].T_wc.matrix()).cwiseAbs().maxCoeff());
    diff_ac = std::max(diff_ac, (a[k].T_wc.matrix() - c[k].T_wc.matrix()).cwiseAbs().maxCoeff());
  }
  EXPECT_EQ(diff_ab, 0.0);
  EXPECT_GT(diff_ac, 0.01);
}

TEST(SynthMotion, ResampleInterpolatesTranslationLinearlyAndRotationAlongTheGeodesic) {
  // Two poses 0.1 s apart with a 0.2 rad rotation about a fixed axis and a 10 cm step:
  // at 30 Hz the frame times are 0, 1/30, 2/30, 3/30 -> fractions 0, 1/3, 2/3, 1.
  Trajectory m(2);
  m[0].timestamp = 5.0;
  m[1].timestamp = 5.1;
  const Eigen::Vector3d axis = Eigen::Vector3d(1, 2, 2).normalized();
  m[0].T_wc.linear() = se3::so3_exp(0.1 * axis);
  m[1].T_wc.linear() = se3::so3_exp(0.3 * axis);
  m[1].T_wc.translation() = Eigen::Vector3d(0.1, 0, 0);
  const Trajectory r = synth::resample_trajectory(m, 0.0, 4, 30.0, "two poses");
  ASSERT_EQ(r.size(), 4u);
  for (int k = 0; k < 4; ++k) {
    const double s = k / 3.0;
    EXPECT_NEAR(r[k].timestamp, 5.0 + k / 30.0, 1e-12);
    EXPECT_NEAR(r[k].T_wc.translation().x(), 0.1 * s, 1e-9);
    EXPECT_LT((r[k].T_wc.linear() - se3::so3_exp((0.1 + 0.2 * s) * axis)).cwiseAbs().maxCoeff(), 1e-9);
  }
  EXPECT_THROW(synth::resample_trajectory(m, 0.0, 5, 30.0, "two poses"), bivo::Error);
  EXPECT_THROW(synth::resample_trajectory(m, -1.0, 2, 30.0, "two poses"), bivo::Error);
}

TEST(SynthMotion, AnchoringKeepsRelativeMotion) {
  synth::HandheldMotionOptions o;
  const Trajectory t = synth::generate_handheld_motion(o);
  Eigen::Isometry3d nominal = se3::exp((se3::Vector6d() << 1, -2, 0.5, 0.3, -0.2, 1.0).finished());
  const Eigen::Isometry3d A = synth::anchor_transform(t[50].T_wc, nominal);
  EXPECT_LT(((A * t[50].T_wc).matrix() - nominal.matrix()).cwiseAbs().maxCoeff(), 1e-12);
  const Eigen::Isometry3d rel = t[10].T_wc.inverse() * t[90].T_wc;
  const Eigen::Isometry3d rel_anchored = (A * t[10].T_wc).inverse() * (A * t[90].T_wc);
  EXPECT_LT((rel.matrix() - rel_anchored.matrix()).cwiseAbs().maxCoeff(), 1e-12);
}
