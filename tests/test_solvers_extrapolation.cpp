// Extrapolated Gauss-Newton steps (SolverOptions::max_step_extrapolation) against closed
// forms: the IRLS fixed point with frozen weights, the limit of a constant contraction, and
// the plain solve an all-refused extrapolation must reproduce iterate for iterate.
#include <cmath>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "tests/solvers_test_problems.h"
#include "tests/test_support.h"

#include "solvers/outer_loop.h"

using namespace bivo;
using bivo::testing::Counting;
using bivo::testing::rel_err;
using bivo::testing::ReweightedLinearPair;

namespace {

// F_1 = (x - c)^2 in one dimension, with a model whose curvature is k times the true one (as
// IRLS weights overstate it): Gauss-Newton steps d = -(x - c) / k shrink by rho = 1 - 1/k per
// iteration. Within `cliff` of c the objective jumps by 100, so a step landing there raises
// the merit.
class InflatedCurvature final : public solvers::BiObjectiveProblem {
 public:
  InflatedCurvature(double c, double k, double cliff) : c_(c), k_(k), cliff_(cliff) {}
  std::string name() const override { return "inflated curvature"; }
  const solvers::Manifold& manifold() const override { return manifold_; }
  solvers::Linearization linearize(const Eigen::VectorXd& x, const solvers::LinearizeOptions&) override {
    solvers::Linearization lin;
    lin.f1.a = evaluate(x)[0];
    lin.f1.b = Eigen::VectorXd::Constant(1, x[0] - c_);
    lin.f1.H = Eigen::MatrixXd::Constant(1, 1, k_);
    lin.f2.a = 0.0;
    lin.f2.b = Eigen::VectorXd::Zero(1);
    lin.f2.H = Eigen::MatrixXd::Zero(1, 1);
    return lin;
  }
  std::array<double, 2> evaluate(const Eigen::VectorXd& x) override {
    const double e = x[0] - c_;
    return {e * e + (std::abs(e) < cliff_ ? 100.0 : 0.0), 0.0};
  }
  solvers::ResidualData residuals(int, const Eigen::VectorXd&, bool) override { return {}; }

 private:
  double c_, k_, cliff_;
  solvers::EuclideanManifold manifold_{1};
};

}  // namespace

TEST(SolversExtrapolation, ExtrapolatedStepsReachTheIrlsFixedPointInFewerIterations) {
  ReweightedLinearPair p(21);
  solvers::SolverOptions opt;
  opt.max_iterations = 500;
  opt.relative_decrease_tolerance = 1e-16;
  opt.step_tolerance = 1e-11;
  Eigen::VectorXd x_plain = Eigen::VectorXd::Zero(4), x_extrapolated = Eigen::VectorXd::Zero(4);
  const auto plain = solvers::solve(p, solvers::WeightedSum(0.5), "gn", x_plain, opt);
  // The merit is that of the latest weights, which the plain step minimizes exactly here
  // (linear residuals): a factor s changes it by -s (2 - s) of the plain decrease, so only
  // factors below 2 can pass the merit test (71 plain iterations, 40 with a cap of 1.9).
  opt.max_step_extrapolation = 1.9;
  const auto extrapolated = solvers::solve(p, solvers::WeightedSum(0.5), "gn", x_extrapolated, opt);
  ASSERT_TRUE(extrapolated.converged()) << extrapolated.FullReport();
  EXPECT_LT(rel_err(x_extrapolated, p.frozen_weight_optimum(x_extrapolated, 0.5)), 1e-7);
  EXPECT_LT(rel_err(x_extrapolated, x_plain), 1e-7);
  EXPECT_EQ(plain.extrapolated_steps, 0);
  EXPECT_GT(extrapolated.extrapolated_steps, 0);
  EXPECT_LT(extrapolated.iterations, 0.7 * plain.iterations) << plain.iterations << " plain iterations\n"
                                                             << extrapolated.FullReport();
  EXPECT_NE(extrapolated.FullReport().find("Extrapolated steps"), std::string::npos);
}

TEST(SolversExtrapolation, ExtrapolationIsTheGeometricTailOfAConstantContraction) {
  // rho = 0.8: after two plain steps the third, extrapolated by 1 / (1 - rho) = 5, lands on c.
  InflatedCurvature p(3.0, 5.0, 0.0);
  solvers::SolverOptions opt;
  opt.max_iterations = 10;
  opt.step_tolerance = 1e-9;
  opt.relative_decrease_tolerance = 0.0;
  opt.max_step_extrapolation = 10.0;
  Eigen::VectorXd x = Eigen::VectorXd::Constant(1, 13.0);
  const auto s = solvers::solve(p, solvers::WeightedSum(0.0), "gn", x, opt);
  ASSERT_GE(s.records.size(), 2u);
  EXPECT_EQ(s.records[0].step_scale, 1.0);  // no previous step yet
  EXPECT_NEAR(s.records[1].step_scale, 5.0, 1e-9) << s.FullReport();
  EXPECT_NEAR(s.records[1].x[0], 3.0, 1e-9);
  // A cap below 5 takes the capped step, and the next factor still recovers rho = 0.8.
  // (After a step taken 3 times the next plain step is 1 - 3 (1 - rho) = 0.4 of it.)
  opt.max_step_extrapolation = 3.0;
  x = Eigen::VectorXd::Constant(1, 13.0);
  const auto capped = solvers::solve(p, solvers::WeightedSum(0.0), "gn", x, opt);
  ASSERT_GE(capped.records.size(), 3u);
  EXPECT_NEAR(capped.records[1].step_scale, 3.0, 1e-12);
  EXPECT_NEAR(capped.records[2].step_scale, 3.0, 1e-12) << capped.FullReport();
  EXPECT_NEAR(capped.records[2].x[0] - 3.0, 10.0 * 0.8 * 0.4 * 0.4, 1e-9);
}

TEST(SolversExtrapolation, AnExtrapolationThatRaisesTheMeritIsRefusedForThePlainStep) {
  // Every extrapolation lands within the cliff: all are refused, and the solve is the plain
  // one, iterate for iterate, with one evaluation more per refusal.
  InflatedCurvature inner(3.0, 5.0, 1.0);
  Counting plain_count(inner), extrapolated_count(inner);
  solvers::SolverOptions opt;
  opt.max_iterations = 8;
  opt.step_tolerance = 1e-9;
  opt.relative_decrease_tolerance = 0.0;
  Eigen::VectorXd x_plain = Eigen::VectorXd::Constant(1, 13.0), x_extrapolated = x_plain;
  const auto plain = solvers::solve(plain_count, solvers::WeightedSum(0.0), "gn", x_plain, opt);
  opt.max_step_extrapolation = 10.0;
  const auto refused = solvers::solve(extrapolated_count, solvers::WeightedSum(0.0), "gn", x_extrapolated, opt);
  ASSERT_EQ(plain.records.size(), refused.records.size());
  for (std::size_t i = 0; i < plain.records.size(); ++i) {
    EXPECT_EQ(plain.records[i].x[0], refused.records[i].x[0]) << "iteration " << i + 1;
    EXPECT_EQ(refused.records[i].step_scale, 1.0);
  }
  EXPECT_EQ(refused.extrapolated_steps, 0);
  EXPECT_GT(refused.refused_extrapolations, 0);
  EXPECT_EQ(extrapolated_count.evaluations + extrapolated_count.evaluations_only,
            plain_count.evaluations + plain_count.evaluations_only + refused.refused_extrapolations);
}
