// Robust weights (robust_weights.h): the t-distribution scale is its own fixed point on data
// with outliers; Huber's scale is 1.4826 median |r|; unit weights without a kind.
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "odometry/robust_weights.h"
#include "solvers/error.h"

using namespace bivo;
using namespace bivo::odometry;

TEST(RobustWeights, TDistributionScaleIsTheFixedPoint) {
  std::mt19937 rng(3);
  std::normal_distribution<float> gauss(0.0f, 4.0f);
  std::vector<float> r(20000);
  std::vector<unsigned char> valid(r.size(), 1);
  for (auto& x : r) x = gauss(rng);
  for (int i = 0; i < 500; ++i) r[static_cast<std::size_t>(i)] = 200.0f;  // outliers
  valid[7] = 0;
  std::vector<float> w(r.size());
  WeightOptions o;
  o.scale_tolerance = 1e-10;
  const double sigma = compute_weights(r.data(), valid.data(), r.size(), o, w.data());
  double acc = 0.0;
  int n = 0;
  for (std::size_t i = 0; i < r.size(); ++i) {
    if (!valid[i]) continue;
    acc += double(r[i]) * r[i] * 6.0 / (5.0 + double(r[i]) * r[i] / (sigma * sigma));
    ++n;
  }
  EXPECT_NEAR(acc / n, sigma * sigma, 1e-5 * sigma * sigma);
  EXPECT_LT(sigma, 8.0);  // the outliers do not blow the scale up (plain RMS would be ~32)
  EXPECT_EQ(w[7], 0.0f);
  EXPECT_NEAR(w[100], 6.0 / (5.0 + double(r[100]) * r[100] / (sigma * sigma)), 1e-6);
  EXPECT_LT(w[0], 0.02f);
}

TEST(RobustWeights, HuberAndNone) {
  std::vector<float> r = {0.1f, -0.2f, 0.3f, 10.0f, -0.1f};
  std::vector<unsigned char> valid(r.size(), 1);
  std::vector<float> w(r.size());
  WeightOptions o;
  o.kind = WeightKind::kHuber;
  const double sigma = compute_weights(r.data(), valid.data(), r.size(), o, w.data());
  EXPECT_NEAR(sigma, 1.4826 * 0.2, 1e-6);  // median |r| = 0.2
  EXPECT_FLOAT_EQ(w[0], 1.0f);
  EXPECT_NEAR(w[3], 1.345 * sigma / 10.0, 1e-6);
  o.kind = WeightKind::kNone;
  compute_weights(r.data(), valid.data(), r.size(), o, w.data());
  EXPECT_FLOAT_EQ(w[3], 1.0f);
  EXPECT_EQ(parse_weight_kind("huber"), WeightKind::kHuber);
  EXPECT_THROW(parse_weight_kind("cauchy"), Error);
}
