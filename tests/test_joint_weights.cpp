// The joint (bivariate t) weights of method "joint" (odometry/joint_weights.h, Kerl et al.
// IROS 2013): a hand-solved fixed point, an independent double-precision oracle of the
// fixed point S = mean(w r r^T), w = (nu + 2) / (nu + r^T S^-1 r), and the marginal weights of
// terms with one valid residual.
#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Dense>
#include <gtest/gtest.h>

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
  const JointScale s = compute_joint_weights(ri.data(), rd.data(), valid.data(), valid.data(), 4, o, wi.data(), wd.data());
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

// Correlated residuals (rho = 0.6) with outliers against a plain double implementation.
TEST(JointWeights, MatchesADoublePrecisionFixedPoint) {
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0.0, 1.0);
  const int n = 5000;
  std::vector<float> ri(n), rd(n);
  std::vector<unsigned char> vi(n, 1), vd(n, 1);
  for (int k = 0; k < n; ++k) {
    const double z1 = g(rng), z2 = g(rng);
    const double heavy = (k % 37 == 0) ? 8.0 : 1.0;  // outliers: what the t-distribution is for
    ri[k] = static_cast<float>(heavy * 6.0 * z1);
    rd[k] = static_cast<float>(heavy * 0.004 * (0.6 * z1 + 0.8 * z2));
  }
  vd[3] = 0;  // one term with intensity only, one with depth only
  vi[4] = 0;
  std::vector<float> wi(n), wd(n);
  WeightOptions o;
  o.max_scale_iterations = 500;
  o.scale_tolerance = 1e-10;
  const JointScale s = compute_joint_weights(ri.data(), rd.data(), vi.data(), vd.data(), n, o, wi.data(), wd.data());

  // Oracle: the same fixed point in double with Eigen, over the terms valid in both.
  const double nu = 5.0;
  Eigen::Matrix2d S = Eigen::Matrix2d::Zero();
  int m = 0;
  for (int k = 0; k < n; ++k) {
    if (!(vi[k] && vd[k])) continue;
    const Eigen::Vector2d r(ri[k], rd[k]);
    S += r * r.transpose();
    ++m;
  }
  S /= m;
  for (int it = 0; it < 2000; ++it) {
    const Eigen::Matrix2d inv = S.inverse();
    Eigen::Matrix2d next = Eigen::Matrix2d::Zero();
    for (int k = 0; k < n; ++k) {
      if (!(vi[k] && vd[k])) continue;
      const Eigen::Vector2d r(ri[k], rd[k]);
      next += (nu + 2.0) / (nu + r.dot(inv * r)) * r * r.transpose();
    }
    S = next / m;
  }
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
