// The depth noise exponent (RgbdProblemOptions::depth_noise_exponent) against the depths read
// from the reference image, the float kernels' F_D, and the method defaults.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "odometry/odometry_methods.h"
#include "odometry/rgbd_problem.h"
#include "solvers/error.h"
#include "tests/support/plane_scene.h"

using namespace bivo;
using namespace bivo::odometry;
using bivo::testing::near_truth;
using bivo::testing::scene;

// The depth noise exponent p divides each term's r_D and its Jacobian row by z^p, z the
// reference pixel's depth: checked against the depths read from the reference image (terms
// are its pixels with depth in [min_depth, max_depth], row by row).
TEST(DepthNoiseExponent, DividesEachDepthTermByItsDepthToThePower) {
  const RgbdLevel& a = scene().reference.pyramid.levels[1];
  const RgbdLevel& b = scene().current.pyramid.levels[1];
  std::vector<double> z;
  for (const float d : a.depth.data) {
    if (d >= 0.1f && d <= 10.0f) z.push_back(d);
  }
  const Eigen::VectorXd x = near_truth();
  RgbdProblemOptions plain;
  plain.weights.kind = WeightKind::kNone;
  RgbdOdometryProblem p0(a, b, plain);
  ASSERT_EQ(static_cast<std::size_t>(p0.num_terms()), z.size());
  const solvers::ResidualData d0 = p0.residuals(2, x, true);
  for (const int exponent : {1, 2, 3}) {
    RgbdProblemOptions o = plain;
    o.depth_noise_exponent = exponent;
    RgbdOdometryProblem p(a, b, o);
    const solvers::ResidualData d = p.residuals(2, x, true);
    Eigen::VectorXd scale(d0.r.size());
    for (Eigen::Index k = 0; k < scale.size(); ++k) scale(k) = std::pow(z[static_cast<std::size_t>(k)], -exponent);
    EXPECT_LT((d.r - scale.cwiseProduct(d0.r)).norm(), 1e-12 * d0.r.norm()) << exponent;
    EXPECT_LT((d.J - scale.asDiagonal() * d0.J).norm(), 1e-12 * d0.J.norm()) << exponent;
    // The float kernels' F_D (unit weights) is the sum of the scaled squares.
    const double want = d.r.squaredNorm();
    EXPECT_NEAR(p.evaluate(x)[1], want, 1e-4 * want) << exponent;
    // The plane lies 1.4-2 m away: the scale leaves r_D's sum between (1/2)^2p and (1/1.4)^2p of it.
    EXPECT_LT(want, std::pow(1 / 1.4, 2 * exponent) * d0.r.squaredNorm());
    EXPECT_GT(want, std::pow(0.5, 2 * exponent) * d0.r.squaredNorm());
  }
  RgbdProblemOptions bad = plain;
  bad.depth_noise_exponent = 4;
  EXPECT_THROW(RgbdOdometryProblem(a, b, bad), Error);
}

TEST(DepthNoiseExponent, AutoIsTwoForTheJointWeightsAndZeroForThePapersMethods) {
  for (const std::string& m : method_names()) {
    const Method method = parse_method(m);
    EXPECT_EQ(method_depth_noise_exponent(method, -1), uses_joint_weights(method) ? 2 : 0) << m;
    EXPECT_EQ(method_depth_noise_exponent(method, 1), 1) << m;  // a request is kept
  }
}
