// Step backends against independent oracles: the Gauss-Newton and exact QCQP steps on linear
// least-squares pairs (whose quadratic models are exact, so one step lands on the closed-form
// optimum computed by QR), the exact step against a brute-force bisection on mu (dense LU, no
// Newton) and the KKT conditions, and the rank-deficient / inactive / infeasible cases.
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "tests/test_support.h"

#include "problems/linear_least_squares_pair.h"
#include "solvers/backend_registry.h"
#include "solvers/error.h"
#include "solvers/scalarization.h"
#include "solvers/step/exact_qcqp.h"
#include "solvers/step/gauss_newton.h"
#include "solvers/step/levenberg_marquardt.h"

using namespace bivo;
using bivo::problems::LinearLeastSquaresPair;
using bivo::solvers::QuadraticModel;

using bivo::testing::rel_err;

namespace {

std::string scientific(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3e", v);
  return buf;
}

LinearLeastSquaresPair draw_problem(int draw, std::mt19937_64& rng) {
  std::uniform_int_distribution<int> dim(2, 8);
  const int n = dim(rng);
  return draw % 2 == 0 ? LinearLeastSquaresPair::well_conditioned(n, rng())
                       : LinearLeastSquaresPair::ill_conditioned(n, rng(), 1e3);
}

Eigen::VectorXd random_vector(int n, std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::VectorXd v(n);
  for (int i = 0; i < n; ++i) v(i) = g(rng);
  return v;
}

// A least-squares model from random J (rows x n), r, w: H = J^T W J, b = J^T W r, a = r^T W r.
QuadraticModel random_model(int n, int rows, double scale, std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> u(0.5, 2.0);
  Eigen::MatrixXd J(rows, n);
  Eigen::VectorXd r(rows), w(rows);
  for (int i = 0; i < rows; ++i) {
    for (int j = 0; j < n; ++j) J(i, j) = scale * g(rng);
    r(i) = scale * g(rng);
    w(i) = u(rng);
  }
  QuadraticModel m;
  m.a = r.dot(w.cwiseProduct(r));
  m.b = J.transpose() * w.cwiseProduct(r);
  m.H = J.transpose() * w.asDiagonal() * J;
  return m;
}

// Brute force: bisection on log mu of phi(mu) = m2(d(mu)) with d(mu) by full-pivot LU.
struct BruteForce {
  Eigen::VectorXd d;
  double mu;
};
Eigen::VectorXd d_of(const QuadraticModel& m1, const QuadraticModel& m2, double mu) {
  return (m1.H + mu * m2.H).fullPivLu().solve(-(m1.b + mu * m2.b));
}
BruteForce brute_force_active(const QuadraticModel& m1, const QuadraticModel& m2, double eps) {
  double lo = 1e-12, hi = 1e12;
  for (int i = 0; i < 300; ++i) {
    const double mid = std::sqrt(lo * hi);
    (m2.value(d_of(m1, m2, mid)) > eps ? lo : hi) = mid;
  }
  return {d_of(m1, m2, hi), hi};
}

}  // namespace

TEST(SolversGaussNewtonStep, OneStepReachesClosedFormOn100RandomDraws) {
  std::mt19937_64 rng(20261122);
  solvers::GaussNewtonBackend gn;
  double worst = 0.0;
  for (int draw = 0; draw < 100; ++draw) {
    auto p = draw_problem(draw, rng);
    const double lambda = std::pow(10.0, std::uniform_real_distribution<double>(-3, 3)(rng));
    const Eigen::VectorXd x = random_vector(p.dim(), rng);
    const auto lin = p.linearize(x, {});
    const solvers::WeightedSum ws(lambda);
    const auto step = gn.solve(ws.make_subproblem(lin));
    EXPECT_DOUBLE_EQ(step.multiplier, lambda);
    const double e = rel_err(x + step.delta, p.weighted_sum_optimum(lambda));
    worst = std::max(worst, e);
    EXPECT_LT(e, 1e-8) << p.name() << " lambda " << lambda;
  }
  RecordProperty("worst_relative_error", scientific(worst));
}

TEST(SolversLevenbergMarquardtStep, UndampedLimitIsGaussNewtonAndDampingShortensTheStep) {
  std::mt19937_64 rng(7);
  auto p = LinearLeastSquaresPair::well_conditioned(5, 3);
  const Eigen::VectorXd x = random_vector(5, rng);
  const auto lin = p.linearize(x, {});
  const auto sp = solvers::WeightedSum(0.7).make_subproblem(lin);
  solvers::LevenbergMarquardtOptions tiny;
  tiny.initial_damping = 1e-14;
  solvers::LevenbergMarquardtBackend lm_tiny(tiny);
  EXPECT_LT(rel_err(x + lm_tiny.solve(sp).delta, p.weighted_sum_optimum(0.7)), 1e-8);
  solvers::LevenbergMarquardtOptions big;
  big.initial_damping = 10.0;
  solvers::LevenbergMarquardtBackend lm_big(big);
  const double short_norm = lm_big.solve(sp).delta.norm();
  EXPECT_LT(short_norm, lm_tiny.solve(sp).delta.norm());
  // Damping grows on rejection and shrinks on acceptance.
  lm_big.on_step_evaluated(false);
  EXPECT_DOUBLE_EQ(lm_big.damping(), 40.0);
  lm_big.on_step_evaluated(true);
  EXPECT_NEAR(lm_big.damping(), 40.0 / 3.0, 1e-12);
}

TEST(SolversExactStep, OneStepReachesClosedFormEpsilonOptimumOn100RandomDraws) {
  std::mt19937_64 rng(11);
  solvers::ExactQcqpBackend exact;
  double worst = 0.0;
  for (int draw = 0; draw < 100; ++draw) {
    auto p = draw_problem(draw, rng);
    const double f2_lo = p.objectives(p.minimizer(2))[1];
    const double f2_hi = p.objectives(p.minimizer(1))[1];
    const double eps = f2_lo + std::uniform_real_distribution<double>(0.02, 0.98)(rng) * (f2_hi - f2_lo);
    const Eigen::VectorXd x = random_vector(p.dim(), rng);
    const auto lin = p.linearize(x, {});
    const auto step = exact.solve(solvers::EpsilonConstraint(eps).make_subproblem(lin));
    const auto oracle = p.epsilon_constraint_optimum(eps);
    ASSERT_TRUE(step.feasible);
    const double e = rel_err(x + step.delta, oracle.x);
    worst = std::max(worst, e);
    EXPECT_LT(e, 1e-8) << p.name() << " eps " << eps;
    EXPECT_NEAR(step.multiplier, oracle.mu, 1e-6 * oracle.mu);
  }
  RecordProperty("worst_relative_error", scientific(worst));
}

TEST(SolversExactStep, MatchesBruteForceMuAndSatisfiesKktOn100RandomModels) {
  std::mt19937_64 rng(12345);
  int active = 0, inactive = 0, infeasible = 0;
  for (int draw = 0; draw < 100; ++draw) {
    const int n = 6;
    // Odometry-like scales: intensity models ~1e4 larger than depth models.
    const QuadraticModel m1 = random_model(n, 40, 30.0, rng);
    const QuadraticModel m2 = random_model(n, 40, 0.05, rng);
    const Eigen::VectorXd d0 = (m1.H).ldlt().solve(-m1.b);
    const Eigen::VectorXd d2 = (m2.H).ldlt().solve(-m2.b);
    const double lo = m2.value(d2), hi = m2.value(d0);
    // Mostly active; every 10th inactive, every 10th (offset 5) infeasible.
    double eps = lo + std::uniform_real_distribution<double>(0.01, 0.99)(rng) * (hi - lo);
    if (draw % 10 == 0) eps = hi * 1.5;
    if (draw % 10 == 5) eps = lo * 0.5;
    const auto q = solvers::solve_qcqp_exact(m1, m2, eps);
    ASSERT_TRUE(q.delta.allFinite());
    if (draw % 10 == 0) {
      ++inactive;
      EXPECT_EQ(q.mu, 0.0);
      EXPECT_LT(rel_err(q.delta, d0), 1e-10);
      continue;
    }
    if (draw % 10 == 5) {
      ++infeasible;
      EXPECT_FALSE(q.feasible);
      EXPECT_TRUE(std::isinf(q.mu));
      EXPECT_LT(rel_err(q.delta, d2), 1e-9);
      EXPECT_NEAR(q.min_m2, lo, 1e-12 * lo);
      continue;
    }
    ++active;
    const BruteForce bf = brute_force_active(m1, m2, eps);
    EXPECT_NEAR(q.mu, bf.mu, 1e-8 * bf.mu);
    EXPECT_LT(rel_err(q.delta, bf.d), 1e-8);
    // KKT: stationarity, feasibility, complementarity, dual feasibility.
    const Eigen::VectorXd grad = (m1.H * q.delta + m1.b) + q.mu * (m2.H * q.delta + m2.b);
    const double grad_scale = m1.b.norm() + q.mu * m2.b.norm() + (m1.H.norm() + q.mu * m2.H.norm()) * q.delta.norm();
    EXPECT_LT(grad.norm(), 1e-10 * grad_scale);
    EXPECT_LE(m2.value(q.delta) - eps, 1e-10 * eps);
    EXPECT_LT(q.mu * std::abs(m2.value(q.delta) - eps), 1e-10 * q.mu * eps);
    EXPECT_GE(q.mu, 0.0);
  }
  EXPECT_EQ(active, 80);
  EXPECT_EQ(inactive, 10);
  EXPECT_EQ(infeasible, 10);
}

TEST(SolversExactStep, TrustRegionSpecialCaseMatchesClosedForm) {
  // m2 = |d|^2 (H2 = I, b2 = 0, a2 = 0) and H1 = diag(h): the step is d_i = -b_i / (h_i + mu)
  // with |d|^2 = eps; check against the secular equation solved independently.
  Eigen::VectorXd h(3), b(3);
  h << 1.0, 4.0, 9.0;
  b << 1.0, -2.0, 0.5;
  QuadraticModel m1, m2;
  m1.H = h.asDiagonal();
  m1.b = b;
  m2.H = Eigen::MatrixXd::Identity(3, 3);
  m2.b = Eigen::VectorXd::Zero(3);
  const double eps = 0.25;  // unconstrained |d|^2 = 1 + 0.25 + 0.0031 > eps: active
  const auto q = solvers::solve_qcqp_exact(m1, m2, eps);
  const auto norm2 = [&](double mu) { return (b.array() / (h.array() + mu)).square().sum(); };
  double lo = 0.0, hi = 100.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (norm2(mid) > eps ? lo : hi) = mid;
  }
  EXPECT_NEAR(q.mu, hi, 1e-12);
  EXPECT_NEAR(q.delta.squaredNorm(), eps, 1e-14);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(q.delta(i), -b(i) / (h(i) + hi), 1e-13);
}

TEST(SolversExactStep, RankDeficientModelsGiveMinimumNormLexicographicSteps) {
  // H1 singular along e3 (m1 flat there), H2 acts on e3 only: for mu > 0 H1 + mu H2 is PD.
  QuadraticModel m1, m2;
  m1.H = Eigen::Vector3d(2.0, 1.0, 0.0).asDiagonal();
  m1.b = Eigen::Vector3d(-2.0, 1.0, 0.0);
  m1.a = 10.0;
  m2.H = Eigen::Vector3d(0.0, 0.0, 1.0).asDiagonal();
  m2.b = Eigen::Vector3d(0.0, 0.0, -3.0);
  m2.a = 9.0;  // m2 = (d3 - 3)^2, independent of m1's variables
  // Inactive: argmin m1 is the line (1, -1, t); m2's best on it is t = 3 with m2 = 0.
  auto q = solvers::solve_qcqp_exact(m1, m2, 1.0);
  EXPECT_EQ(q.mu, 0.0);
  EXPECT_LT((q.delta - Eigen::Vector3d(1.0, -1.0, 3.0)).norm(), 1e-12);
  // A common null direction: both models ignore e4; the step must have no e4 component.
  QuadraticModel n1, n2;
  n1.H = Eigen::Vector4d(1.0, 1.0, 0.0, 0.0).asDiagonal();
  n1.b = Eigen::Vector4d(-1.0, -1.0, 0.0, 0.0);
  n2.H = Eigen::Vector4d(1.0, 0.0, 1.0, 0.0).asDiagonal();
  n2.b = Eigen::Vector4d(1.0, 0.0, -1.0, 0.0);
  n2.a = 2.0;  // m2 = (d1 + 1)^2 + (d3 - 1)^2
  // Unconstrained m1-minimizer d = (1, 1, t, 0); min over t of m2 = 4 at t = 1. eps = 1 active.
  q = solvers::solve_qcqp_exact(n1, n2, 1.0);
  ASSERT_TRUE(q.feasible);
  EXPECT_NEAR(q.delta(3), 0.0, 1e-14);
  EXPECT_NEAR(q.delta(2), 1.0, 1e-12);
  // d1(mu) = (1 - mu)/(1 + mu), m2 = (d1 + 1)^2 = 4/(1+mu)^2 = 1 -> mu = 1, d1 = 0.
  EXPECT_NEAR(q.mu, 1.0, 1e-10);
  EXPECT_NEAR(q.delta(0), 0.0, 1e-10);
  EXPECT_NEAR(n2.value(q.delta), 1.0, 1e-12);
}

TEST(SolversExactStep, EpsilonBelowMinimumIsFlaggedInfeasibleNotNaN) {
  std::mt19937_64 rng(3);
  const QuadraticModel m1 = random_model(6, 20, 1.0, rng);
  const QuadraticModel m2 = random_model(6, 20, 1.0, rng);
  const Eigen::VectorXd d2 = m2.H.ldlt().solve(-m2.b);
  solvers::ExactQcqpBackend exact;
  solvers::Linearization lin;
  lin.f1 = m1;
  lin.f2 = m2;
  const auto step = exact.solve(solvers::EpsilonConstraint(0.0).make_subproblem(lin));
  EXPECT_FALSE(step.feasible);
  EXPECT_TRUE(step.delta.allFinite());
  EXPECT_LT(rel_err(step.delta, d2), 1e-9);
}

TEST(SolversGaussNewtonStep, RankDeficientSystemGivesMinimumNormSolution) {
  // H = diag(2, 0): the minimum-norm solution of H d = -b with b = (-4, 0) is (2, 0).
  solvers::Linearization lin;
  lin.f1.H = Eigen::Vector2d(2.0, 0.0).asDiagonal();
  lin.f1.b = Eigen::Vector2d(-4.0, 0.0);
  lin.f2.H = Eigen::Matrix2d::Zero();
  lin.f2.b = Eigen::Vector2d::Zero();
  solvers::GaussNewtonBackend gn;
  const auto step = gn.solve(solvers::WeightedSum(1.0).make_subproblem(lin));
  EXPECT_NEAR(step.delta(0), 2.0, 1e-14);
  EXPECT_NEAR(step.delta(1), 0.0, 1e-14);
}

TEST(SolversScalarization, PoliciesAreCalledWithTheLinearizationAndValidated) {
  solvers::Linearization lin;
  lin.f1.H = Eigen::Matrix2d::Identity();
  lin.f1.b = Eigen::Vector2d(1.0, 2.0);
  lin.f1.a = 3.0;
  lin.f2 = lin.f1;
  const solvers::WeightedSum ws([](const solvers::Linearization& l) { return l.f1.a * 2.0; });
  EXPECT_DOUBLE_EQ(ws.make_subproblem(lin).lambda, 6.0);
  const solvers::EpsilonConstraint ec([](const solvers::Linearization& l) { return l.f2.a / 3.0; });
  EXPECT_DOUBLE_EQ(ec.make_subproblem(lin).epsilon, 1.0);
  const solvers::WeightedSum bad([](const solvers::Linearization&) { return -1.0; });
  EXPECT_THROW(bad.make_subproblem(lin), Error);
  const solvers::EpsilonConstraint bad_eps([](const solvers::Linearization&) { return NAN; });
  EXPECT_THROW(bad_eps.make_subproblem(lin), Error);
}

TEST(SolversBadInput, NegativeOrNaNParametersAndBrokenModelsThrowNamingTheValue) {
  try {
    solvers::WeightedSum ws(-0.5);
    FAIL() << "no throw";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("-0.5"), std::string::npos) << e.what();
  }
  EXPECT_THROW(solvers::WeightedSum{std::nan("")}, Error);
  EXPECT_THROW(solvers::WeightedSum{std::numeric_limits<double>::infinity()}, Error);
  EXPECT_THROW(solvers::EpsilonConstraint{-1.0}, Error);
  EXPECT_THROW(solvers::EpsilonConstraint{std::nan("")}, Error);
  EXPECT_THROW(solvers::WeightedSum{solvers::LambdaPolicy{}}, Error);
  QuadraticModel m;
  m.H = Eigen::Matrix2d::Identity();
  m.b = Eigen::Vector2d::Zero();
  EXPECT_THROW(solvers::solve_qcqp_exact(m, m, -1.0), Error);
  QuadraticModel wrong = m;
  wrong.b = Eigen::Vector3d::Zero();
  EXPECT_THROW(solvers::solve_qcqp_exact(m, wrong, 1.0), Error);
  QuadraticModel nan = m;
  nan.H(0, 1) = NAN;
  EXPECT_THROW(solvers::solve_qcqp_exact(m, nan, 1.0), Error);
  solvers::Linearization lin;
  lin.f1 = m;
  lin.f2 = wrong;
  EXPECT_THROW(solvers::WeightedSum(1.0).make_subproblem(lin), Error);
}

TEST(SolversRegistry, NamesDescriptionsAndUnknownNameListsValidOnes) {
  for (const char* name : {"gn", "lm", "exact", "ceres"}) EXPECT_TRUE(solvers::has_backend(name)) << name;
  EXPECT_TRUE(solvers::backend_info("gn").weighted_sum);
  EXPECT_FALSE(solvers::backend_info("gn").epsilon_constraint);
  EXPECT_TRUE(solvers::backend_info("exact").epsilon_constraint);
  EXPECT_TRUE(solvers::is_whole_problem_backend("ceres"));
  EXPECT_EQ(solvers::make_step_backend("lm")->name(), "lm");
  EXPECT_THROW(solvers::make_step_backend("ceres"), Error);
  try {
    solvers::make_step_backend("newton-raphson");
    FAIL() << "no throw";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("newton-raphson"), std::string::npos);
    EXPECT_NE(msg.find("gn"), std::string::npos);
    EXPECT_NE(msg.find("exact"), std::string::npos);
  }
  for (const auto& info : solvers::backend_infos()) {
    EXPECT_FALSE(info.description.empty()) << info.name;
    EXPECT_NE(solvers::backend_help().find(info.name), std::string::npos);
  }
}
