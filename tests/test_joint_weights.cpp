// The joint (bivariate t) weights of method "joint" (odometry/joint_weights.h, Kerl et al.
// IROS 2013): a hand-solved fixed point, an independent double-precision oracle of the
// fixed point S = mean(w r r^T), w = (nu + 2) / (nu + r^T S^-1 r), and the marginal weights of
// terms with one valid residual.
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "odometry/joint_weights.h"

using namespace bivo::odometry;

// r = (+-a, 0), (0, +-b): by symmetry S = diag(s1, s2), and s1 = 1/4 * 2 a^2 * 7 / (5 + a^2 / s1)
// gives a^2 / s1 = 2, i.e. S = diag(a^2 / 2, b^2 / 2), every weight (5 + 2) / (5 + 2) = 1.
TEST(JointWeights, HandSolvedSymmetricExample) {
  const float a = 4.0f, b = 0.02f;
  const std::vector<float> ri = {a, -a, 0.0f, 0.0f}, rd = {0.0f, 0.0f, b, -b};
  const std::vector<unsigned char> valid(4, 1);
  std::vector<float> wi(4), wd(4);
  WeightOptions o;
  o.max_scale_iterations = 200;
  o.scale_tolerance = 1e-9;
  const JointScale s =
      compute_joint_weights(ri.data(), rd.data(), valid.data(), valid.data(), 4, o, wi.data(), wd.data());
  EXPECT_NEAR(s.s_ii, 8.0, 8.0 * 1e-5);
  EXPECT_NEAR(s.s_dd, 2e-4, 2e-4 * 1e-5);
  EXPECT_NEAR(s.s_id, 0.0, 1e-9);
  EXPECT_NEAR(s.implied_lambda(), 4e4, 4e4 * 2e-5);
  EXPECT_NEAR(s.correlation(), 0.0, 1e-6);
  for (int k = 0; k < 4; ++k) {
    EXPECT_NEAR(wi[k], 1.0, 1e-5) << k;
    EXPECT_EQ(wi[k], wd[k]) << "one weight per pixel";
  }
}

namespace {

// Correlated residuals (rho = 0.6) with outliers, one term with intensity only (3) and one
// with depth only (4).
struct CorrelatedResiduals {
  explicit CorrelatedResiduals(int n) : ri(n), rd(n), vi(n, 1), vd(n, 1) {
    std::mt19937 rng(7);
    std::normal_distribution<double> g(0.0, 1.0);
    for (int k = 0; k < n; ++k) {
      const double z1 = g(rng), z2 = g(rng);
      const double heavy = (k % 37 == 0) ? 8.0 : 1.0;  // outliers: what the t-distribution is for
      ri[k] = static_cast<float>(heavy * 6.0 * z1);
      rd[k] = static_cast<float>(heavy * 0.004 * (0.6 * z1 + 0.8 * z2));
    }
    vd[3] = 0;
    vi[4] = 0;
  }
  std::vector<float> ri, rd;
  std::vector<unsigned char> vi, vd;
};

// The plain fixed point S <- mean(w r r^T) in double over the terms valid in both, from the
// marginal second moments, until S changes by <= tolerance (relative, as the estimator's
// stopping rule), or from `start`; *iterations counts its steps.
Eigen::Matrix2d plain_fixed_point(const CorrelatedResiduals& d, double nu, double tolerance, int* iterations,
                                  const Eigen::Matrix2d* start = nullptr) {
  const std::size_t n = d.ri.size();
  Eigen::Matrix2d S = Eigen::Matrix2d::Zero();
  int m = 0;
  for (std::size_t k = 0; k < n; ++k) {
    if (!(d.vi[k] && d.vd[k])) continue;
    const Eigen::Vector2d r(d.ri[k], d.rd[k]);
    S += r * r.transpose();
    ++m;
  }
  S /= m;
  S(0, 1) = S(1, 0) = 0.0;
  if (start) S = *start;
  for (*iterations = 1; *iterations <= 5000; ++*iterations) {
    const Eigen::Matrix2d inv = S.inverse();
    Eigen::Matrix2d next = Eigen::Matrix2d::Zero();
    for (std::size_t k = 0; k < n; ++k) {
      if (!(d.vi[k] && d.vd[k])) continue;
      const Eigen::Vector2d r(d.ri[k], d.rd[k]);
      next += (nu + 2.0) / (nu + r.dot(inv * r)) * r * r.transpose();
    }
    next /= m;
    const double change = std::abs(next(0, 0) - S(0, 0)) / S(0, 0) + std::abs(next(1, 1) - S(1, 1)) / S(1, 1) +
                          std::abs(next(0, 1) - S(0, 1)) / std::sqrt(S(0, 0) * S(1, 1));
    S = next;
    if (change <= tolerance) break;
  }
  return S;
}

}  // namespace

// Against a plain double implementation of the fixed point.
TEST(JointWeights, MatchesADoublePrecisionFixedPoint) {
  const int n = 5000;
  const CorrelatedResiduals data(n);
  const auto& [ri, rd, vi, vd] = data;
  std::vector<float> wi(n), wd(n);
  WeightOptions o;
  o.max_scale_iterations = 500;
  o.scale_tolerance = 1e-10;
  const JointScale s = compute_joint_weights(ri.data(), rd.data(), vi.data(), vd.data(), n, o, wi.data(), wd.data());

  // Oracle: the same fixed point in double with Eigen, over the terms valid in both.
  const double nu = 5.0;
  int iterations = 0;
  const Eigen::Matrix2d S = plain_fixed_point(data, nu, 1e-14, &iterations);
  EXPECT_NEAR(s.s_ii, S(0, 0), 1e-4 * S(0, 0));
  EXPECT_NEAR(s.s_dd, S(1, 1), 1e-4 * S(1, 1));
  EXPECT_NEAR(s.s_id, S(0, 1), 1e-4 * std::sqrt(S(0, 0) * S(1, 1)));
  EXPECT_NEAR(s.correlation(), S(0, 1) / std::sqrt(S(0, 0) * S(1, 1)), 1e-4);
  EXPECT_GT(s.correlation(), 0.4);  // the data's correlation is seen
  const Eigen::Matrix2d inv = S.inverse();
  for (int k : {0, 1, 37, 74, 100}) {
    const Eigen::Vector2d r(ri[k], rd[k]);
    const double w = (nu + 2.0) / (nu + r.dot(inv * r));
    EXPECT_NEAR(wi[k], w, 1e-4 * w) << k;
    EXPECT_EQ(wi[k], wd[k]) << k;
  }
  EXPECT_LT(wi[37], 0.5 * wi[1]) << "an outlier is down-weighted";
  // Marginals of the bivariate t: univariate t with scale S_jj.
  EXPECT_NEAR(wi[3], (nu + 1.0) / (nu + double(ri[3]) * ri[3] / S(0, 0)), 1e-4);
  EXPECT_EQ(wd[3], 0.0f);
  EXPECT_NEAR(wd[4], (nu + 1.0) / (nu + double(rd[4]) * rd[4] / S(1, 1)), 1e-4);
  EXPECT_EQ(wi[4], 0.0f);
}

TEST(JointWeights, NoValidResidualGivesUnitWeightsAndNoScale) {
  const std::vector<float> r = {1.0f, 2.0f};
  const std::vector<unsigned char> none(2, 0), all(2, 1);
  std::vector<float> wi(2, 5.0f), wd(2, 5.0f);
  const JointScale s = compute_joint_weights(r.data(), r.data(), all.data(), none.data(), 2, {}, wi.data(), wd.data());
  EXPECT_FALSE(s.valid());
  EXPECT_EQ(s.implied_lambda(), 0.0);
  EXPECT_EQ(wi[0], 1.0f);
  EXPECT_EQ(wd[0], 0.0f);
}

// Newton on the fixed point: the same S as the plain iteration run to 1e-14, in fewer passes
// than the plain iteration stopped by the same rule at the same tolerance, and closer to it.
// Cold (from the marginal moments) and warm (from a nearby S, as the tracker starts it from
// the previous linearization's).
TEST(JointWeights, NewtonReachesTheFixedPointInAFewPasses) {
  const int n = 5000;
  const CorrelatedResiduals data(n);
  std::vector<float> wi(n), wd(n);
  WeightOptions o;
  o.max_scale_iterations = 50;
  o.scale_tolerance = 1e-4;  // the tracker's default
  int exact_iterations = 0;
  const Eigen::Matrix2d exact = plain_fixed_point(data, o.nu, 1e-14, &exact_iterations);
  const auto error = [&](double s_ii, double s_id, double s_dd) {
    return std::abs(s_ii - exact(0, 0)) / exact(0, 0) + std::abs(s_dd - exact(1, 1)) / exact(1, 1) +
           std::abs(s_id - exact(0, 1)) / std::sqrt(exact(0, 0) * exact(1, 1));
  };
  Eigen::Matrix2d near;
  near << 1.3 * exact(0, 0), 0.7 * exact(0, 1), 0.7 * exact(0, 1), 1.2 * exact(1, 1);
  for (const bool warm : {false, true}) {
    SCOPED_TRACE(warm ? "warm" : "cold");
    const JointScale initial = warm ? JointScale{near(0, 0), near(0, 1), near(1, 1)} : JointScale{};
    const JointScale s = compute_joint_weights(data.ri.data(), data.rd.data(), data.vi.data(), data.vd.data(), n, o,
                                               wi.data(), wd.data(), initial);
    int plain_iterations = 0;
    const Eigen::Matrix2d plain =
        plain_fixed_point(data, o.nu, o.scale_tolerance, &plain_iterations, warm ? &near : nullptr);
    EXPECT_LE(s.passes, warm ? 4 : 5);
    EXPECT_GE(plain_iterations, 2 * s.passes) << plain_iterations << " plain, " << s.passes << " Newton";
    EXPECT_LT(error(s.s_ii, s.s_id, s.s_dd), 1e-6);
    EXPECT_LT(error(s.s_ii, s.s_id, s.s_dd), 0.1 * error(plain(0, 0), plain(0, 1), plain(1, 1)));
  }
}

// Depth that fits to the last bit (a flat wall, r_D ~ 1e-20 m): S_DD falls below what float can
// invert, and the joint precision would be inf and the weights 0 * inf = NaN. Such a scale
// weighs as none: every weight finite (unit), and the t-scale model alike.
TEST(JointWeights, AScaleWithoutAFloatInverseGivesUnitWeights) {
  std::mt19937 rng(7);
  std::normal_distribution<float> gray(0.0f, 4.0f), tiny(0.0f, 1e-21f);
  const std::size_t n = 4000;
  std::vector<float> r_i(n), r_d(n), w_i(n), w_d(n);
  std::vector<unsigned char> valid(n, 1);
  for (std::size_t k = 0; k < n; ++k) r_i[k] = gray(rng), r_d[k] = tiny(rng);
  WeightOptions o;
  const JointScale s =
      compute_joint_weights(r_i.data(), r_d.data(), valid.data(), valid.data(), n, o, w_i.data(), w_d.data());
  EXPECT_GT(s.s_dd, 0.0);
  EXPECT_FALSE(std::isfinite(static_cast<float>(s.s_ii / s.determinant())));  // the case at hand
  for (std::size_t k = 0; k < n; ++k) {
    ASSERT_EQ(w_i[k], 1.0f) << k;
    ASSERT_EQ(w_d[k], 1.0f) << k;
  }
  const WeightModel t = weight_model(o, 4.0, 1e-21);
  EXPECT_EQ(t.depth.inv_scale2, ObjectiveWeights{}.inv_scale2);  // unit
  EXPECT_GT(t.intensity.inv_scale2, 0.06f);
}
