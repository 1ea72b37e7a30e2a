// Pareto sweeps against the analytic fronts of the linear pairs (QR closed forms), the
// dominance filter, the knee and the hypervolume against hand-computed values.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include <gtest/gtest.h>

#include "tests/test_support.h"

#include "problems/exponential_decay_pair.h"
#include "problems/linear_least_squares_pair.h"
#include "solvers/error.h"
#include "solvers/pareto.h"

using namespace bivo;
using bivo::problems::LinearLeastSquaresPair;
using bivo::solvers::ParetoPoint;

using bivo::testing::rel_err;

namespace {

ParetoPoint pt(double f1, double f2) {
  ParetoPoint p;
  p.f1 = f1;
  p.f2 = f2;
  return p;
}

// Independent pairwise check (not solvers::dominates).
void expect_mutually_nondominated(const std::vector<ParetoPoint>& pts) {
  for (std::size_t i = 0; i < pts.size(); ++i) {
    for (std::size_t j = 0; j < pts.size(); ++j) {
      if (i == j) continue;
      const bool worse_or_equal = pts[j].f1 >= pts[i].f1 && pts[j].f2 >= pts[i].f2;
      EXPECT_FALSE(worse_or_equal) << "point " << j << " (" << pts[j].f1 << ", " << pts[j].f2
                                   << ") is dominated by or equal to point " << i << " (" << pts[i].f1 << ", "
                                   << pts[i].f2 << ")";
    }
  }
}

solvers::ParetoOptions tight(int points) {
  solvers::ParetoOptions o;
  o.points = points;
  o.solver.relative_decrease_tolerance = 1e-20;
  o.solver.step_tolerance = 1e-12;
  return o;
}

}  // namespace

TEST(SolversPareto, LambdaSweepReproducesTheAnalyticFront) {
  for (auto p :
       {LinearLeastSquaresPair::well_conditioned(5, 31), LinearLeastSquaresPair::ill_conditioned(5, 32, 1e3)}) {
    const auto front = solvers::sweep_lambda(p, Eigen::VectorXd::Zero(5), tight(25));
    ASSERT_EQ(front.all.size(), 25u);
    EXPECT_EQ(front.dropped, 0) << p.name();
    ASSERT_EQ(front.points.size(), 25u);
    for (const auto& q : front.points) {
      const Eigen::VectorXd want = p.weighted_sum_optimum(q.parameter);
      EXPECT_LT(rel_err(q.x, want), 1e-6) << p.name() << " lambda " << q.parameter;
      const auto f = p.objectives(want);
      EXPECT_NEAR(q.f1, f[0], 1e-6 * std::max(1.0, f[0]));
      EXPECT_NEAR(q.f2, f[1], 1e-6 * std::max(1.0, f[1]));
    }
    expect_mutually_nondominated(front.points);
    for (std::size_t i = 1; i < front.points.size(); ++i) EXPECT_LT(front.points[i - 1].f1, front.points[i].f1);
  }
}

TEST(SolversPareto, EpsilonSweepReproducesTheAnalyticFrontAndItsRange) {
  for (auto p :
       {LinearLeastSquaresPair::well_conditioned(4, 41), LinearLeastSquaresPair::ill_conditioned(6, 42, 1e3)}) {
    const int n = p.dim();
    const auto front = solvers::sweep_epsilon(p, Eigen::VectorXd::Zero(n), tight(15));
    const double f2_min = p.objectives(p.minimizer(2))[1];
    const double f2_at_f1_min = p.objectives(p.minimizer(1))[1];
    EXPECT_NEAR(front.f2_min, f2_min, 1e-9 * f2_min) << p.name();
    EXPECT_NEAR(front.f2_at_f1_min, f2_at_f1_min, 1e-9 * f2_at_f1_min) << p.name();
    ASSERT_EQ(front.all.size(), 15u);
    for (const auto& q : front.all) {
      const auto oracle = p.epsilon_constraint_optimum(q.parameter);
      // The tight end (epsilon = min F2) has no finite multiplier; it is the F2-minimizer.
      EXPECT_LT(rel_err(q.x, oracle.x), 1e-6) << p.name() << " eps " << q.parameter;
      EXPECT_LE(q.f2, q.parameter * (1.0 + 1e-9));
    }
    EXPECT_GE(front.points.size(), 14u);  // the two ends may coincide numerically with neighbours only
    expect_mutually_nondominated(front.points);
  }
}

TEST(SolversPareto, WarmStartedLambdaSweepFollowsTheNonlinearOracle) {
  auto p = bivo::problems::ExponentialDecayPair::synthetic(60, 17);
  auto o = tight(9);
  o.lambda_min = 1e-2;
  o.lambda_max = 1e2;
  o.solver.max_iterations = 200;
  const auto front = solvers::sweep_lambda(p, Eigen::Vector3d(1.0, 1.0, 1.0), o);
  ASSERT_EQ(front.points.size(), 9u);
  for (const auto& q : front.points) {
    EXPECT_TRUE(q.converged) << "lambda " << q.parameter;
    EXPECT_LT(rel_err(q.x, p.weighted_sum_optimum(q.parameter)), 1e-7) << "lambda " << q.parameter;
  }
  expect_mutually_nondominated(front.points);
  const auto knee = solvers::knee_index(front.points);
  ASSERT_TRUE(knee.has_value());
  EXPECT_GT(*knee, 0u);
  EXPECT_LT(*knee, 8u);
}

// The secant predictor changes where a point starts, not what it is: with and without it the
// points are the oracle's optima, and on this smooth front it saves iterations.
TEST(SolversPareto, SecantPredictorKeepsEveryPointAtItsOptimum) {
  auto p = bivo::problems::ExponentialDecayPair::synthetic(60, 17);
  auto o = tight(17);
  o.lambda_min = 1e-2;
  o.lambda_max = 1e2;
  o.solver.max_iterations = 200;
  int iterations[2] = {0, 0};
  for (bool predict : {false, true}) {
    o.secant_predictor = predict;
    const auto front = solvers::sweep_lambda(p, Eigen::Vector3d(1.0, 1.0, 1.0), o);
    ASSERT_EQ(front.all.size(), 17u);
    for (const auto& q : front.all) {
      EXPECT_TRUE(q.converged) << "lambda " << q.parameter;
      EXPECT_LT(rel_err(q.x, p.weighted_sum_optimum(q.parameter)), 1e-7) << "lambda " << q.parameter;
      iterations[predict] += q.iterations;
    }
  }
  std::printf("iterations without / with the predictor: %d / %d\n", iterations[0], iterations[1]);
  EXPECT_LT(iterations[1], iterations[0]);
}

namespace {

// Fails every solve started from a secant prediction: while the latest linearization was made
// at a point no evaluation had visited (a predicted start; x0 excepted), evaluations away from
// that point return NaN, so such a solve ends in kNumericalFailure after its first step.
class FailsFromPredictions final : public solvers::BiObjectiveProblem {
 public:
  FailsFromPredictions(solvers::BiObjectiveProblem& inner, const Eigen::VectorXd& x0) : inner_(inner) {
    visited_.push_back(x0);
  }
  std::string name() const override { return inner_.name(); }
  const solvers::Manifold& manifold() const override { return inner_.manifold(); }
  solvers::Linearization linearize(const Eigen::VectorXd& x, const solvers::LinearizeOptions& o) override {
    fresh_ = std::find(visited_.begin(), visited_.end(), x) == visited_.end();
    predicted_starts += fresh_ ? 1 : 0;
    linearized_at_ = x;
    return inner_.linearize(x, o);
  }
  std::array<double, 2> evaluate(const Eigen::VectorXd& x) override {
    if (fresh_ && x != linearized_at_) return {NAN, NAN};
    visited_.push_back(x);
    return inner_.evaluate(x);
  }
  solvers::ResidualData residuals(int j, const Eigen::VectorXd& x, bool J) override {
    return inner_.residuals(j, x, J);
  }
  int predicted_starts = 0;

 private:
  solvers::BiObjectiveProblem& inner_;
  std::vector<Eigen::VectorXd> visited_;
  Eigen::VectorXd linearized_at_;
  bool fresh_ = false;
};

}  // namespace

// A predicted solve that fails numerically falls back to the plain warm start from the
// previous point (not to where the failed solve last linearized), and every point still
// reaches its optimum.
TEST(SolversPareto, AFailedPredictionFallsBackToThePreviousPoint) {
  auto p = bivo::problems::ExponentialDecayPair::synthetic(60, 17);
  const Eigen::VectorXd x0 = Eigen::Vector3d(1.0, 1.0, 1.0);
  FailsFromPredictions failing(p, x0);
  auto o = tight(17);
  o.lambda_min = 1e-2;
  o.lambda_max = 1e2;
  o.solver.max_iterations = 200;
  const auto front = solvers::sweep_lambda(failing, x0, o);
  EXPECT_GT(failing.predicted_starts, 2) << "no prediction was tried: the test proves nothing";
  ASSERT_EQ(front.all.size(), 17u);
  for (const auto& q : front.all) {
    EXPECT_TRUE(q.converged) << "lambda " << q.parameter;
    EXPECT_LT(rel_err(q.x, p.weighted_sum_optimum(q.parameter)), 1e-7) << "lambda " << q.parameter;
  }
}

TEST(SolversPareto, DominatedPointsAndDuplicatesAreDropped) {
  const std::vector<ParetoPoint> pts = {pt(1, 5), pt(2, 2), pt(3, 3), pt(2, 2), pt(4, 1), pt(5, 1), pt(0.5, 9)};
  const auto nd = solvers::nondominated(pts);
  ASSERT_EQ(nd.size(), 4u);
  EXPECT_EQ(nd[0].f1, 0.5);
  EXPECT_EQ(nd[1].f1, 1.0);
  EXPECT_EQ(nd[2].f1, 2.0);
  EXPECT_EQ(nd[3].f1, 4.0);
  EXPECT_TRUE(solvers::dominates(pt(1, 1), pt(1, 2)));
  EXPECT_FALSE(solvers::dominates(pt(1, 1), pt(1, 1)));
  EXPECT_FALSE(solvers::dominates(pt(1, 3), pt(2, 2)));
}

TEST(SolversPareto, KneeIsFarthestFromTheChordInNormalizedSpace) {
  // Normalized front (0,1), (0.1,0.3), (0.5,0.1), (1,0): distances to x + y = 1 are
  // 0, 0.6/sqrt2, 0.4/sqrt2, 0 -> knee at index 1.
  std::vector<ParetoPoint> front = {pt(0, 1), pt(0.1, 0.3), pt(0.5, 0.1), pt(1, 0)};
  ASSERT_TRUE(solvers::knee_index(front).has_value());
  EXPECT_EQ(*solvers::knee_index(front), 1u);
  // Units must not matter: scale F2 by 1e6 and shift F1.
  for (auto& p : front) {
    p.f2 *= 1e6;
    p.f1 = 3.0 + 7.0 * p.f1;
  }
  EXPECT_EQ(*solvers::knee_index(front), 1u);
  EXPECT_FALSE(solvers::knee_index({pt(0, 1), pt(1, 0)}).has_value());
}

TEST(SolversPareto, HypervolumeMatchesHandComputedArea) {
  // Staircase (1,3), (2,2), (3,1) below (4,4): 3*1 + 2*1 + 1*1 = 6.
  std::vector<ParetoPoint> pts = {pt(2, 2), pt(1, 3), pt(3, 1)};
  EXPECT_DOUBLE_EQ(solvers::hypervolume(pts, 4, 4), 6.0);
  pts.push_back(pt(3, 3));    // dominated: adds nothing
  pts.push_back(pt(5, 0.5));  // outside the reference box: ignored
  EXPECT_DOUBLE_EQ(solvers::hypervolume(pts, 4, 4), 6.0);
  EXPECT_DOUBLE_EQ(solvers::hypervolume({}, 4, 4), 0.0);
  EXPECT_THROW(solvers::hypervolume(pts, NAN, 4), Error);
}

TEST(SolversPareto, BadSweepOptionsThrow) {
  auto p = LinearLeastSquaresPair::well_conditioned(3, 1);
  solvers::ParetoOptions o;
  o.points = 1;
  EXPECT_THROW(solvers::sweep_lambda(p, Eigen::VectorXd::Zero(3), o), Error);
  o.points = 5;
  o.lambda_min = 0.0;
  EXPECT_THROW(solvers::sweep_lambda(p, Eigen::VectorXd::Zero(3), o), Error);
  o.lambda_min = 10.0;
  o.lambda_max = 1.0;
  EXPECT_THROW(solvers::sweep_lambda(p, Eigen::VectorXd::Zero(3), o), Error);
  EXPECT_THROW(solvers::sweep_epsilon(p, Eigen::VectorXd::Zero(4), solvers::ParetoOptions{}), Error);
}
