// The outer loop and the whole-problem backend against independent oracles: QR closed forms
// on the linear pairs, the variable-projection optimum of the exponential-decay pair, GN vs
// Ceres on an SE(3) alignment problem, the KKT link between the epsilon-constraint and the
// weighted sum (x_eps = argmin F1 + mu F2), and the failure paths (NaN, bad input).
#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "tests/solvers_test_problems.h"
#include "tests/test_support.h"

#include "problems/exponential_decay_pair.h"
#include "problems/linear_least_squares_pair.h"
#include "problems/point_alignment_pair.h"
#include "solvers/backend_registry.h"
#include "solvers/error.h"
#include "solvers/geometry/se3.h"
#include "solvers/outer_loop.h"

using namespace bivo;
using bivo::problems::ExponentialDecayPair;
using bivo::problems::LinearLeastSquaresPair;
using bivo::problems::PointAlignmentPair;

using bivo::testing::Counting;
using bivo::testing::rel_err;
using bivo::testing::ReweightedLinearPair;

namespace {

// Wraps a problem and turns its objectives into NaN outside the ball |x| <= radius.
class NanBeyond final : public solvers::BiObjectiveProblem {
 public:
  NanBeyond(solvers::BiObjectiveProblem& inner, double radius) : inner_(inner), radius_(radius) {}
  std::string name() const override { return "NaN beyond |x| = " + std::to_string(radius_); }
  const solvers::Manifold& manifold() const override { return inner_.manifold(); }
  solvers::Linearization linearize(const Eigen::VectorXd& x, const solvers::LinearizeOptions& o) override {
    auto lin = inner_.linearize(x, o);
    if (x.norm() > radius_) lin.f1.a = NAN;
    return lin;
  }
  std::array<double, 2> evaluate(const Eigen::VectorXd& x) override {
    if (x.norm() > radius_) return {NAN, NAN};
    return inner_.evaluate(x);
  }
  solvers::ResidualData residuals(int j, const Eigen::VectorXd& x, bool J) override {
    return inner_.residuals(j, x, J);
  }

 private:
  solvers::BiObjectiveProblem& inner_;
  double radius_;
};

// Returns models of the wrong size.
class WrongSizeModels final : public solvers::BiObjectiveProblem {
 public:
  std::string name() const override { return "wrong-size models"; }
  const solvers::Manifold& manifold() const override { return manifold_; }
  solvers::Linearization linearize(const Eigen::VectorXd&, const solvers::LinearizeOptions&) override {
    solvers::Linearization lin;
    lin.f1.b = Eigen::VectorXd::Zero(3);
    lin.f1.H = Eigen::MatrixXd::Identity(3, 3);
    lin.f2 = lin.f1;
    return lin;
  }
  std::array<double, 2> evaluate(const Eigen::VectorXd&) override { return {0.0, 0.0}; }
  solvers::ResidualData residuals(int, const Eigen::VectorXd&, bool) override { return {}; }

 private:
  solvers::EuclideanManifold manifold_{2};
};

}  // namespace

TEST(SolversOuterLoop, EveryWeightedSumBackendReachesTheClosedFormOnLinearPairs) {
  std::mt19937_64 rng(99);
  for (int draw = 0; draw < 100; ++draw) {
    auto p = draw % 2 ? LinearLeastSquaresPair::ill_conditioned(6, rng(), 1e3)
                      : LinearLeastSquaresPair::well_conditioned(6, rng());
    const double lambda = std::pow(10.0, std::uniform_real_distribution<double>(-2, 2)(rng));
    const Eigen::VectorXd want = p.weighted_sum_optimum(lambda);
    for (const char* backend : {"gn", "lm", "ceres"}) {
      Eigen::VectorXd x = Eigen::VectorXd::Zero(6);
      solvers::SolverOptions opt;
      opt.max_iterations = 100;
      opt.relative_decrease_tolerance = 1e-20;  // compare optima, not early stops
      opt.step_tolerance = 1e-12;
      const auto s = solvers::solve(p, solvers::WeightedSum(lambda), backend, x, opt);
      EXPECT_LT(rel_err(x, want), 1e-8) << backend << " " << p.name() << "\n" << s.FullReport();
      EXPECT_TRUE(s.converged()) << backend << s.FullReport();
    }
  }
}

TEST(SolversOuterLoop, ExactBackendReachesTheEpsilonOptimumOnLinearPairs) {
  std::mt19937_64 rng(5);
  for (int draw = 0; draw < 20; ++draw) {
    auto p = draw % 2 ? LinearLeastSquaresPair::ill_conditioned(6, rng(), 1e3)
                      : LinearLeastSquaresPair::well_conditioned(6, rng());
    const double lo = p.objectives(p.minimizer(2))[1], hi = p.objectives(p.minimizer(1))[1];
    const double eps = lo + 0.3 * (hi - lo);
    Eigen::VectorXd x = Eigen::VectorXd::Zero(6);
    const auto s = solvers::solve(p, solvers::EpsilonConstraint(eps), "exact", x);
    const auto oracle = p.epsilon_constraint_optimum(eps);
    EXPECT_LT(rel_err(x, oracle.x), 1e-8) << s.FullReport();
    EXPECT_TRUE(s.feasible);
    EXPECT_NEAR(s.multiplier, oracle.mu, 1e-6 * oracle.mu);
    EXPECT_LE(s.final_f2, eps * (1 + 1e-10));
  }
}

TEST(SolversOuterLoop, GaussNewtonLevenbergMarquardtAndCeresAgreeOnTheNonlinearPair) {
  auto p = ExponentialDecayPair::synthetic(60, 17);
  for (double lambda : {0.1, 1.0, 10.0}) {
    const Eigen::VectorXd want = p.weighted_sum_optimum(lambda);
    for (const char* backend : {"gn", "lm", "ceres"}) {
      Eigen::VectorXd x = Eigen::Vector3d(1.0, 1.0, 1.0);
      solvers::SolverOptions opt;
      opt.max_iterations = 200;
      opt.relative_decrease_tolerance = 1e-20;
      opt.step_tolerance = 1e-12;
      const auto s = solvers::solve(p, solvers::WeightedSum(lambda), backend, x, opt);
      EXPECT_LT(rel_err(x, want), 1e-7) << backend << " lambda " << lambda << "\n" << s.FullReport();
      EXPECT_TRUE(s.converged()) << s.FullReport();
    }
  }
}

TEST(SolversOuterLoop, EpsilonOptimumOfTheNonlinearPairIsTheWeightedSumOptimumAtMu) {
  // KKT of eq. `bounded objective form`: at the optimum, x minimizes F1 + mu F2 (a local
  // statement; the instance's g(k) has one minimum on [0.05, 5]).
  auto p = ExponentialDecayPair::synthetic(60, 17);
  Eigen::VectorXd x1 = p.weighted_sum_optimum(0.0), x2 = p.weighted_sum_optimum(1e6);
  const double f2_hi = p.evaluate(x1)[1], f2_lo = p.evaluate(x2)[1];
  const double eps = f2_lo + 0.2 * (f2_hi - f2_lo);
  Eigen::VectorXd x = Eigen::Vector3d(1.0, 1.0, 1.0);
  solvers::SolverOptions opt;
  opt.max_iterations = 200;
  opt.relative_decrease_tolerance = 1e-20;
  opt.step_tolerance = 1e-12;
  const auto s = solvers::solve(p, solvers::EpsilonConstraint(eps), "exact", x, opt);
  ASSERT_TRUE(s.converged()) << s.FullReport();
  EXPECT_TRUE(s.feasible);
  EXPECT_NEAR(s.final_f2, eps, 1e-9 * eps);
  EXPECT_LT(rel_err(x, p.weighted_sum_optimum(s.multiplier)), 1e-6) << "mu " << s.multiplier;
}

TEST(SolversOuterLoop, GaussNewtonAndCeresAgreeOnSe3) {
  PointAlignmentPair p(4);
  for (double lambda : {0.2, 5.0}) {
    Eigen::VectorXd x_gn = solvers::se3::to_ambient(Eigen::Isometry3d::Identity());
    Eigen::VectorXd x_ceres = x_gn;
    solvers::SolverOptions opt;
    opt.relative_decrease_tolerance = 1e-20;
    opt.step_tolerance = 1e-13;
    const auto a = solvers::solve(p, solvers::WeightedSum(lambda), "gn", x_gn, opt);
    const auto b = solvers::solve(p, solvers::WeightedSum(lambda), "ceres", x_ceres, opt);
    ASSERT_TRUE(a.converged()) << a.FullReport();
    ASSERT_TRUE(b.converged()) << b.FullReport();
    const auto Ta = solvers::se3::from_ambient(x_gn), Tb = solvers::se3::from_ambient(x_ceres);
    EXPECT_LT(solvers::se3::log(Ta * Tb.inverse()).norm(), 1e-8);
    // Optimality: the weighted-sum gradient b1 + lambda b2 vanishes at both.
    const auto lin = p.linearize(x_ceres, {});
    EXPECT_LT((lin.f1.b + lambda * lin.f2.b).norm(), 1e-8 * (lin.f1.b.norm() + 1.0));
  }
}

TEST(SolversManifold, Se3PlusJacobianAndMinusMatchFiniteDifferences) {
  solvers::Se3Manifold m;
  solvers::se3::Vector6d xi;
  xi << 0.3, -0.1, 0.5, 0.4, -0.7, 0.2;
  const Eigen::VectorXd x = solvers::se3::to_ambient(solvers::se3::exp(xi));
  const Eigen::MatrixXd P = m.plus_jacobian(x);
  const double h = 1e-6;
  for (int k = 0; k < 6; ++k) {
    Eigen::VectorXd e = Eigen::VectorXd::Zero(6);
    e(k) = h;
    Eigen::VectorXd xp = m.retract(x, e), xm = m.retract(x, -e);
    if (xp.tail<4>().dot(x.tail<4>()) < 0) xp.tail<4>() *= -1;  // quaternion sign
    if (xm.tail<4>().dot(x.tail<4>()) < 0) xm.tail<4>() *= -1;
    EXPECT_LT(((xp - xm) / (2 * h) - P.col(k)).norm(), 1e-8) << "column " << k;
  }
  Eigen::VectorXd d(6);
  d << 0.01, 0.02, -0.03, 0.05, -0.02, 0.01;
  EXPECT_LT((m.minus(m.retract(x, d), x) - d).norm(), 1e-12);
  // The generic (finite-difference, Gauss-Newton) defaults of the base class agree.
  EXPECT_LT((m.Manifold::plus_jacobian(x) - P).norm(), 1e-7);
  EXPECT_LT((m.Manifold::minus(m.retract(x, d), x) - d).norm(), 1e-8);
}

TEST(SolversOuterLoop, GaussNewtonAndCeresReachTheSameIrlsFixedPoint) {
  ReweightedLinearPair p(21);
  solvers::SolverOptions opt;
  opt.max_iterations = 500;  // IRLS converges linearly (rate ~0.8 here)
  opt.relative_decrease_tolerance = 1e-16;
  opt.step_tolerance = 1e-11;
  Eigen::VectorXd x_gn = Eigen::VectorXd::Zero(4), x_ceres = Eigen::VectorXd::Zero(4);
  const auto a = solvers::solve(p, solvers::WeightedSum(0.5), "gn", x_gn, opt);
  const auto b = solvers::solve(p, solvers::WeightedSum(0.5), "ceres", x_ceres, opt);
  ASSERT_TRUE(a.converged()) << a.FullReport();
  ASSERT_TRUE(b.converged()) << b.FullReport();
  EXPECT_LT(rel_err(x_gn, p.frozen_weight_optimum(x_gn, 0.5)), 1e-8);
  EXPECT_LT(rel_err(x_ceres, p.frozen_weight_optimum(x_ceres, 0.5)), 1e-8) << b.FullReport();
  EXPECT_LT(rel_err(x_ceres, x_gn), 1e-7);  // both within 1e-8 of a fixed point; IRLS is linear
  EXPECT_GT(rel_err(x_gn, Eigen::VectorXd(p.frozen_weight_optimum(Eigen::VectorXd::Zero(4), 0.5))), 1e-3)
      << "the first weights must not already be the fixed point, or the test proves nothing";
}

TEST(SolversOuterLoop, NaNAfterAStepStopsWithNumericalFailureAndKeepsTheLastGoodX) {
  auto inner = LinearLeastSquaresPair::well_conditioned(4, 8);
  const Eigen::VectorXd opt = inner.weighted_sum_optimum(1.0);
  NanBeyond p(inner, 0.5 * opt.norm());  // GN's first step lands on the optimum: NaN there
  Eigen::VectorXd x = Eigen::VectorXd::Zero(4);
  const auto s = solvers::solve(p, solvers::WeightedSum(1.0), "gn", x);
  EXPECT_EQ(s.termination, solvers::TerminationReason::kNumericalFailure) << s.FullReport();
  EXPECT_EQ(x, Eigen::VectorXd::Zero(4));
  EXPECT_TRUE(std::isfinite(s.final_f1) && std::isfinite(s.final_f2));
  EXPECT_DOUBLE_EQ(s.final_f1, inner.objectives(x)[0]);
  EXPECT_NE(s.FullReport().find("numerical failure"), std::string::npos);
  EXPECT_FALSE(s.converged());
}

TEST(SolversOuterLoop, SummaryRecordsPhasesIterationsAndAReadableReport) {
  auto p = ExponentialDecayPair::synthetic(40, 2);
  Eigen::VectorXd x = Eigen::Vector3d(1.0, 1.0, 1.0);
  solvers::PhaseProfile profile;
  solvers::SolverOptions opt;
  opt.profile = &profile;
  opt.max_iterations = 3;
  const auto s = solvers::solve(p, solvers::WeightedSum(2.0), "gn", x, opt);
  EXPECT_EQ(s.iterations, 3);
  EXPECT_EQ(s.termination, solvers::TerminationReason::kMaxIterations);
  ASSERT_EQ(s.records.size(), 3u);
  EXPECT_DOUBLE_EQ(s.records.back().f1, s.final_f1);
  EXPECT_DOUBLE_EQ(s.records[0].multiplier, 2.0);
  for (const char* phase : {"subproblem", "residuals", "normal_equations", "other"}) {
    EXPECT_GT(s.phases.seconds(phase), 0.0) << phase;
    EXPECT_DOUBLE_EQ(profile.seconds(phase), s.phases.seconds(phase)) << phase;
  }
  EXPECT_NEAR(s.phases.total_seconds(), s.total_seconds, 1e-12 + 1e-9 * s.total_seconds);
  const std::string report = s.FullReport();
  for (const char* word : {"gn", "weighted sum (lambda = 2)", "F1", "F2", "iteration budget", "subproblem"})
    EXPECT_NE(report.find(word), std::string::npos) << word << "\n" << report;
  // Monotone decrease of the merit over GN iterations on this easy start.
  EXPECT_LT(s.final_f1 + 2.0 * s.final_f2, s.initial_f1 + 2.0 * s.initial_f2);
}

TEST(SolversOuterLoop, BadInputThrows) {
  auto p = LinearLeastSquaresPair::well_conditioned(3, 1);
  Eigen::VectorXd wrong = Eigen::VectorXd::Zero(4);
  EXPECT_THROW(solvers::solve(p, solvers::WeightedSum(1.0), "gn", wrong), Error);
  Eigen::VectorXd nan = Eigen::VectorXd::Zero(3);
  nan(1) = NAN;
  EXPECT_THROW(solvers::solve(p, solvers::WeightedSum(1.0), "gn", nan), Error);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(3);
  EXPECT_THROW(solvers::solve(p, solvers::EpsilonConstraint(1.0), "gn", x), Error);
  EXPECT_THROW(solvers::solve(p, solvers::WeightedSum(1.0), "exact", x), Error);
  EXPECT_THROW(solvers::solve(p, solvers::EpsilonConstraint(1.0), "ceres", x), Error);
  EXPECT_THROW(solvers::solve(p, solvers::WeightedSum(1.0), "no-such-backend", x), Error);
  WrongSizeModels w;
  Eigen::VectorXd x2 = Eigen::VectorXd::Zero(2);
  EXPECT_THROW(solvers::solve(w, solvers::WeightedSum(1.0), "gn", x2), Error);
  NanBeyond starts_bad(p, -1.0);  // |x| > -1 everywhere: NaN already at the start
  EXPECT_THROW(solvers::solve(starts_bad, solvers::WeightedSum(1.0), "gn", x), Error);
}

// A solve started from the previous solve's last linearization (LinearizationCarry) is the
// solve that would have linearized there: the oracle is a second, identical problem taken
// through the same solves without the carry. The robust pair's weights depend on where it
// was last linearized, so a carry made at the wrong point would show.
TEST(SolversOuterLoop, ACarriedLinearizationIsTheSolveThatWouldHaveLinearizedThere) {
  ReweightedLinearPair robust(5), robust_oracle(5);
  Counting problem(robust), oracle(robust_oracle);
  solvers::SolverOptions opt;
  opt.max_iterations = 8;  // IRLS stops on the budget, after an accepted step: x != carry.x
  Eigen::VectorXd x = Eigen::VectorXd::Zero(4), x_oracle = x;
  solvers::LinearizationCarry carry;
  solvers::solve(problem, solvers::WeightedSum(0.5), "gn", x, opt, &carry);
  solvers::solve(oracle, solvers::WeightedSum(0.5), "gn", x_oracle, opt);
  ASSERT_TRUE(carry.lin.has_value());
  ASSERT_NE(carry.x, x) << "the last linearization is one step behind the final x";
  EXPECT_EQ(problem.evaluations_only, 1) << "the budget's last step is evaluated without keeping data";
  EXPECT_EQ(oracle.evaluations_only, 1);

  const int linearized = problem.linearizations, oracle_linearized = oracle.linearizations;
  x = carry.x;
  x_oracle = carry.x;
  const auto a = solvers::solve(problem, solvers::WeightedSum(3.0), "gn", x, opt, &carry);
  const auto b = solvers::solve(oracle, solvers::WeightedSum(3.0), "gn", x_oracle, opt);
  EXPECT_EQ(x, x_oracle);
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_EQ(a.final_f1, b.final_f1);
  EXPECT_EQ(a.final_f2, b.final_f2);
  EXPECT_EQ(problem.linearizations - linearized, oracle.linearizations - oracle_linearized - 1);

  // Another x: the carry is not used.
  Eigen::VectorXd elsewhere = Eigen::VectorXd::Constant(4, 0.1);
  const int before = problem.linearizations;
  solvers::solve(problem, solvers::WeightedSum(3.0), "gn", elsewhere, opt, &carry);
  EXPECT_EQ(problem.linearizations - before, opt.max_iterations)
      << "one at the start, one per accepted step but the last";

  // keep_final_point: the last step is evaluated with evaluate().
  opt.keep_final_point = true;
  const int only_before = problem.evaluations_only;
  solvers::solve(problem, solvers::WeightedSum(3.0), "gn", elsewhere, opt);
  EXPECT_EQ(problem.evaluations_only, only_before);
}
