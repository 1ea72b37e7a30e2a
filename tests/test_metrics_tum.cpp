// TUM RPE/ATE (odometry/io/metrics.h) against hand-built closed-form oracles: constant drift,
// rigidly moved copies, known rotation drift, and an ATE whose optimal alignment is known.
#include <cmath>

#include <gtest/gtest.h>

#include "experiments/trajectory_evaluation.h"
#include "odometry/io/metrics.h"
#include "solvers/error.h"
#include "solvers/geometry/se3.h"

using namespace bivo;
using namespace bivo::odometry;
using namespace bivo::odometry::io;
namespace se3 = bivo::solvers::se3;

namespace {

constexpr double kT0 = 1305031102.0;  // TUM-like absolute stamps exercise double precision

Eigen::Isometry3d rot_z(double a) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return T;
}

// A smooth generic camera motion: helix with a wobbling orientation.
Eigen::Isometry3d generic_pose(double t) {
  se3::Vector6d xi;
  xi << 0.3 * std::cos(t), 0.2 * std::sin(1.3 * t), 0.1 * t, 0.2 * std::sin(t), 0.1 * t, -0.15 * std::cos(0.7 * t);
  return se3::exp(xi);
}

// Ground truth at 100 Hz for `seconds`; pose(t) with t relative to kT0.
template <class F>
Trajectory sampled(F pose, double rate_hz, int count) {
  Trajectory out;
  for (int k = 0; k < count; ++k) {
    const double t = k / rate_hz;
    out.push_back({kT0 + t, pose(t)});
  }
  return out;
}

}  // namespace

TEST(MetricsRpe, ConstantTranslationalDriftGivesThatDriftPerSecond) {
  // Truth moves along x at 0.5 m/s; the estimate additionally drifts 0.07 m/s along y.
  // Each 1-s window then has error translation exactly (0, -0.07, 0) and no rotation.
  const double drift = 0.07;
  const auto gt = sampled(
      [](double t) {
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.translation() = Eigen::Vector3d(0.5 * t, 0, 1);
        return T;
      },
      100.0, 500);
  const auto est = sampled(
      [&](double t) {
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.translation() = Eigen::Vector3d(0.5 * t, drift * t, 1);
        return T;
      },
      25.0, 100);  // 25 Hz, 4 s; every estimate stamp equals a truth stamp to rounding
  const RpeResult r = relative_pose_error(gt, est);
  // Windows i -> i+25; evaluate_rpe.py drops those ending on the last frame: 100 - 26 = 74.
  ASSERT_EQ(r.pairs.size(), 74u);
  EXPECT_NEAR(r.trans_rmse, drift, 1e-9);
  EXPECT_NEAR(r.trans_max, drift, 1e-9);
  EXPECT_NEAR(r.rot_rmse_deg, 0.0, 1e-9);
  for (const auto& p : r.pairs) EXPECT_NEAR(p.t_est_1 - p.t_est_0, 1.0, 1e-6);
}

TEST(MetricsRpe, DeltaScalesTheWindow) {
  const double drift = 0.07;
  const auto gt = sampled(
      [](double t) {
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.translation() = Eigen::Vector3d(0.5 * t, 0, 1);
        return T;
      },
      100.0, 500);
  const auto est = sampled(
      [&](double t) {
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.translation() = Eigen::Vector3d(0.5 * t, drift * t, 1);
        return T;
      },
      25.0, 100);
  RpeOptions o;
  o.delta_s = 0.4;  // 10 frames
  const RpeResult r = relative_pose_error(gt, est, o);
  ASSERT_EQ(r.pairs.size(), 89u);
  EXPECT_NEAR(r.trans_rmse, drift * 0.4, 1e-9);
}

TEST(MetricsRpe, RigidlyMovedCopyHasZeroError) {
  // Left-multiplying every pose by one rigid transform (another world frame) leaves every
  // relative motion unchanged.
  const Eigen::Isometry3d S = se3::exp((se3::Vector6d() << 1.0, -2.0, 0.5, 0.3, -0.8, 1.9).finished());
  const auto gt = sampled(generic_pose, 100.0, 600);
  const auto est = sampled([&](double t) { return S * generic_pose(t); }, 20.0, 120);
  const RpeResult r = relative_pose_error(gt, est);
  EXPECT_EQ(r.pairs.size(), 120u - 21u);
  EXPECT_NEAR(r.trans_rmse, 0.0, 1e-9);
  EXPECT_NEAR(r.rot_rmse_deg, 0.0, 1e-9);
}

TEST(MetricsRpe, KnownRotationDriftAboutTheOpticalAxis) {
  // Truth: no rotation, position p(t). Estimate: same position, orientation Rz(w t).
  // For the window i -> j with d = p_j - p_i: M_g = [I, d], M_e = [Rz(w dt), Rz(-w t_i) d],
  // error = M_e M_g^-1 = [Rz(w dt), Rz(-w t_i) d - Rz(w dt) d], so rot = w dt and
  // trans = |d - Rz(w t_j) d| (derivation in docs/metrics.md).
  const double w = 0.2;  // rad/s
  auto position = [](double t) { return Eigen::Vector3d(0.4 * t, 0.1 * t * t, 2.0 - 0.3 * t); };
  const auto gt = sampled(
      [&](double t) {
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.translation() = position(t);
        return T;
      },
      100.0, 500);
  const auto est = sampled(
      [&](double t) {
        Eigen::Isometry3d T = rot_z(w * t);
        T.translation() = position(t);
        return T;
      },
      25.0, 100);
  const RpeResult r = relative_pose_error(gt, est);
  ASSERT_EQ(r.pairs.size(), 74u);
  double sum_t2 = 0, sum_r2 = 0;
  for (int i = 0; i < 74; ++i) {
    const double ti = i / 25.0, tj = (i + 25) / 25.0;
    const Eigen::Vector3d d = position(tj) - position(ti);
    const Eigen::Vector3d e = d - rot_z(w * tj).linear() * d;
    sum_t2 += e.squaredNorm();
    const double rot_deg = w * (tj - ti) * 180.0 / M_PI;
    sum_r2 += rot_deg * rot_deg;
  }
  EXPECT_NEAR(r.trans_rmse, std::sqrt(sum_t2 / 74), 1e-9);
  EXPECT_NEAR(r.rot_rmse_deg, std::sqrt(sum_r2 / 74), 1e-9);
  EXPECT_NEAR(r.rot_rmse_deg, w * 180.0 / M_PI, 1e-9);
}

TEST(MetricsRpe, SmallStampOffsetsWithinToleranceStillMatch) {
  // Estimate stamps 4 ms after the truth stamps: matched to the nearest truth stamp.
  const auto gt = sampled(generic_pose, 100.0, 400);
  Trajectory est;
  for (int k = 0; k < 80; ++k) est.push_back({kT0 + k / 25.0 + 0.004, generic_pose(k / 25.0)});
  const RpeResult r = relative_pose_error(gt, est);
  EXPECT_EQ(r.pairs.size(), 80u - 26u);
  EXPECT_NEAR(r.trans_rmse, 0.0, 1e-9);
  for (const auto& p : r.pairs) EXPECT_NEAR(p.t_gt_0, p.t_est_0 - 0.004, 1e-6);
}

TEST(MetricsRpe, NoOverlapThrowsNamingTheRanges) {
  const auto gt = sampled(generic_pose, 100.0, 300);
  Trajectory est = sampled(generic_pose, 25.0, 60);
  for (auto& p : est) p.timestamp += 100.0;
  try {
    relative_pose_error(gt, est);
    FAIL() << "expected bivo::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("overlap"), std::string::npos) << e.what();
  }
  EXPECT_THROW(absolute_trajectory_error(gt, est), Error);
}

TEST(MetricsAte, RigidlyTransformedCopyHasZeroErrorAndRecoversTheTransform) {
  const Eigen::Isometry3d S = se3::exp((se3::Vector6d() << 1.0, -2.0, 0.5, 0.3, -0.8, 1.9).finished());
  const auto gt = sampled(generic_pose, 100.0, 600);
  const auto est = sampled([&](double t) { return S * generic_pose(t); }, 20.0, 110);
  const AteResult a = absolute_trajectory_error(gt, est);
  EXPECT_EQ(a.errors.size(), 110u);
  EXPECT_NEAR(a.rmse, 0.0, 1e-9);
  EXPECT_LT((a.alignment.matrix() - S.inverse().matrix()).norm(), 1e-9);
}

TEST(MetricsAte, KnownResidualAfterAlignmentOnACube) {
  // Truth at the 8 cube corners (±1, ±2, ±3); the estimate is each corner pushed by
  // s_k * e along z with s_k = sign(x)sign(y)sign(z), then moved rigidly by S. Because
  // sum_k s_k p_k = 0 the cross-covariance stays symmetric positive definite, so the optimal
  // alignment undoes exactly S and leaves residual e at every corner: ATE = e.
  const double e = 0.05;
  const Eigen::Isometry3d S = se3::exp((se3::Vector6d() << 0.2, 0.1, -0.4, 0.5, 0.2, -0.3).finished());
  Trajectory gt, est;
  int k = 0;
  for (int sx : {-1, 1})
    for (int sy : {-1, 1})
      for (int sz : {-1, 1}) {
        const Eigen::Vector3d p(sx * 1.0, sy * 2.0, sz * 3.0);
        Eigen::Isometry3d G = Eigen::Isometry3d::Identity();
        G.translation() = p;
        Eigen::Isometry3d E = G;
        E.translation() += Eigen::Vector3d(0, 0, sx * sy * sz * e);
        gt.push_back({kT0 + k * 0.1, G});
        est.push_back({kT0 + k * 0.1 + 0.003, S * E});
        ++k;
      }
  const AteResult a = absolute_trajectory_error(gt, est);
  ASSERT_EQ(a.errors.size(), 8u);
  EXPECT_NEAR(a.rmse, e, 1e-9);
  EXPECT_NEAR(a.max, e, 1e-9);
  EXPECT_LT((a.alignment.matrix() - S.inverse().matrix()).norm(), 1e-9);
}

TEST(MetricsAte, ConstantOffsetIsRemovedByAlignment) {
  const auto gt = sampled(generic_pose, 100.0, 300);
  const auto est = sampled(
      [](double t) {
        Eigen::Isometry3d T = generic_pose(t);
        T.translation() += Eigen::Vector3d(3, -1, 2);
        return T;
      },
      25.0, 70);
  EXPECT_NEAR(absolute_trajectory_error(gt, est).rmse, 0.0, 1e-9);
}

TEST(MetricsAssociate, GreedyOneToOneBySmallestDifference) {
  // a[0] and a[1] both lie within 20 ms of b[0]; a[1] is nearer (1 ms vs 16 ms) and takes
  // it, leaving a[0] unmatched; b[1] goes to a[2].
  const std::vector<double> a = {10.000, 10.015, 10.040};
  const std::vector<double> b = {10.016, 10.041, 10.100};
  const auto m = associate_timestamps(a, b, 0.02);
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m[0], std::make_pair(1, 0));
  EXPECT_EQ(m[1], std::make_pair(2, 1));
  // Strictly less than max_dt, as evaluate_ate.py.
  EXPECT_TRUE(associate_timestamps({1.0}, {1.5}, 0.5).empty());
  EXPECT_EQ(associate_timestamps({1.0}, {1.25}, 0.5).size(), 1u);
}

// The windows counted before scoring are the ones relative_pose_error scores: 2 Hz poses over
// 1-s windows, whose end may not be the last pose. "Too short" runs counted one window more
// (4 poses: 2 counted, 1 scored), so such a run failed its cell instead of saying so.
TEST(MetricsRpe, TheWindowCountIsTheScoredWindows) {
  const auto gt = sampled(generic_pose, 100.0, 400);
  for (const auto& [poses, windows] : {std::pair{3, 0}, std::pair{4, 1}, std::pair{5, 2}, std::pair{8, 5}}) {
    const Trajectory est = sampled(generic_pose, 2.0, poses);
    EXPECT_EQ(rpe_window_count(est, 1.0), windows) << poses << " poses";
    if (windows >= 2) {
      EXPECT_EQ(int(relative_pose_error(gt, est).pairs.size()), windows) << poses << " poses";
    } else {
      EXPECT_THROW(relative_pose_error(gt, est), Error) << poses << " poses";
    }
  }
  std::string why;
  EXPECT_FALSE(bivo::experiments::rpe_if_long_enough(gt, sampled(generic_pose, 2.0, 4), 1.0, why));
  EXPECT_EQ(why.rfind("too short", 0), 0u) << why;
}
