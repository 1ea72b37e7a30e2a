// The analytic instances: their Jacobians and models against finite differences, their
// oracles against optimality conditions checked independently, and their input validation.
#include <cmath>

#include <gtest/gtest.h>

#include "problems/exponential_decay_pair.h"
#include "problems/linear_least_squares_pair.h"
#include "solvers/error.h"

using namespace bivo;
using bivo::problems::ExponentialDecayPair;
using bivo::problems::LinearLeastSquaresPair;

namespace {

// Central-difference gradient of f at x.
template <class F>
Eigen::VectorXd fd_gradient(F f, const Eigen::VectorXd& x, double h) {
  Eigen::VectorXd g(x.size());
  for (int k = 0; k < x.size(); ++k) {
    Eigen::VectorXd e = Eigen::VectorXd::Zero(x.size());
    e(k) = h;
    g(k) = (f(x + e) - f(x - e)) / (2 * h);
  }
  return g;
}

}  // namespace

TEST(ProblemsExponentialDecay, JacobiansAndModelsMatchFiniteDifferences) {
  auto p = ExponentialDecayPair::synthetic(30, 3);
  const Eigen::VectorXd x = Eigen::Vector3d(1.7, 4.2, 0.9);
  for (int j = 1; j <= 2; ++j) {
    const auto d = p.residuals(j, x, true);
    for (int k = 0; k < 3; ++k) {
      Eigen::VectorXd e = Eigen::VectorXd::Zero(3);
      e(k) = 1e-6;
      const Eigen::VectorXd fd = (p.residuals(j, x + e, false).r - p.residuals(j, x - e, false).r) / 2e-6;
      EXPECT_LT((fd - d.J.col(k)).norm(), 1e-7 * (1.0 + fd.norm())) << "objective " << j << " column " << k;
    }
  }
  const auto lin = p.linearize(x, {});
  const auto f = p.evaluate(x);
  EXPECT_DOUBLE_EQ(lin.f1.a, f[0]);
  EXPECT_DOUBLE_EQ(lin.f2.a, f[1]);
  // grad F_j = 2 b_j.
  const Eigen::VectorXd g1 = fd_gradient([&](const Eigen::VectorXd& y) { return p.evaluate(y)[0]; }, x, 1e-6);
  EXPECT_LT((g1 - 2.0 * lin.f1.b).norm(), 1e-6 * (1.0 + g1.norm()));
}

TEST(ProblemsExponentialDecay, OracleIsAStationaryPointOfTheWeightedSum) {
  auto p = ExponentialDecayPair::synthetic(60, 17);
  for (double lambda : {0.0, 0.3, 3.0, 100.0}) {
    const Eigen::VectorXd x = p.weighted_sum_optimum(lambda);
    const auto F = [&](const Eigen::VectorXd& y) {
      const auto f = p.evaluate(y);
      return f[0] + lambda * f[1];
    };
    const Eigen::VectorXd g = fd_gradient(F, x, 1e-5);
    EXPECT_LT(g.norm(), 1e-7 * (1.0 + F(x))) << "lambda " << lambda;
    // And a minimum: every coordinate perturbation increases the weighted sum (with
    // lambda = 0, F_2's amplitude c_2 does not enter).
    for (int k = 0; k < 3; ++k) {
      if (lambda == 0.0 && k == 1) continue;
      Eigen::VectorXd e = Eigen::VectorXd::Zero(3);
      e(k) = 1e-3;
      EXPECT_GT(F(x + e), F(x));
      EXPECT_GT(F(x - e), F(x));
    }
  }
  // The two data sets pull the shared rate apart: k moves from ~0.7 towards ~1.4 with lambda.
  EXPECT_LT(p.weighted_sum_optimum(0.01)(2), 0.8);
  EXPECT_GT(p.weighted_sum_optimum(100.0)(2), 1.3);
}

TEST(ProblemsLinearPair, ModelsAreExactAndOraclesSatisfyOptimality) {
  for (auto p : {LinearLeastSquaresPair::well_conditioned(5, 7), LinearLeastSquaresPair::ill_conditioned(5, 8, 1e3)}) {
    const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(5, -1.0, 1.0);
    const auto lin = p.linearize(x, {});
    const Eigen::VectorXd d = Eigen::VectorXd::LinSpaced(5, 0.3, -0.2);
    const auto f = p.objectives(x + d);
    EXPECT_NEAR(lin.f1.value(d), f[0], 1e-10 * f[0]);  // linear residuals: the model is exact
    EXPECT_NEAR(lin.f2.value(d), f[1], 1e-10 * f[1]);
    for (double lambda : {0.01, 1.0, 100.0}) {
      const Eigen::VectorXd xs = p.weighted_sum_optimum(lambda);
      const auto l = p.linearize(xs, {});
      const Eigen::VectorXd g = l.f1.b + lambda * l.f2.b;  // half the gradient of F1 + lambda F2
      EXPECT_LT(g.norm(), 1e-9 * (l.f1.b.norm() + lambda * l.f2.b.norm() + std::sqrt(l.f1.a + lambda * l.f2.a)))
          << p.name() << " lambda " << lambda;
    }
    const double lo = p.objectives(p.minimizer(2))[1], hi = p.objectives(p.minimizer(1))[1];
    ASSERT_LT(lo, hi);
    const double eps = 0.5 * (lo + hi);
    const auto o = p.epsilon_constraint_optimum(eps);
    EXPECT_TRUE(o.feasible);
    EXPECT_GT(o.mu, 0.0);
    EXPECT_NEAR(p.objectives(o.x)[1], eps, 1e-10 * eps);
    const auto l = p.linearize(o.x, {});
    EXPECT_LT((l.f1.b + o.mu * l.f2.b).norm(), 1e-8 * (l.f1.b.norm() + o.mu * l.f2.b.norm()));
    // Inactive and infeasible ends.
    EXPECT_EQ(p.epsilon_constraint_optimum(2.0 * hi).mu, 0.0);
    EXPECT_FALSE(p.epsilon_constraint_optimum(0.5 * lo).feasible);
  }
}

TEST(ProblemsBadInput, MismatchedNonFiniteAndDegenerateDataThrow) {
  const Eigen::MatrixXd A = Eigen::MatrixXd::Identity(3, 2);
  const Eigen::VectorXd y = Eigen::VectorXd::Ones(3), w = Eigen::VectorXd::Ones(3);
  EXPECT_NO_THROW(LinearLeastSquaresPair("ok", A, y, w, A, y, w));
  EXPECT_THROW(LinearLeastSquaresPair("y", A, Eigen::VectorXd::Ones(2), w, A, y, w), Error);
  EXPECT_THROW(LinearLeastSquaresPair("cols", A, y, w, Eigen::MatrixXd::Identity(3, 3), y, w), Error);
  Eigen::VectorXd ynan = y;
  ynan(1) = NAN;
  EXPECT_THROW(LinearLeastSquaresPair("nan", A, ynan, w, A, y, w), Error);
  Eigen::VectorXd wneg = w;
  wneg(0) = -1.0;
  EXPECT_THROW(LinearLeastSquaresPair("neg", A, y, wneg, A, y, w), Error);
  Eigen::MatrixXd rank1 = Eigen::MatrixXd::Zero(3, 2);
  rank1.col(0).setOnes();
  EXPECT_THROW(LinearLeastSquaresPair("rank", rank1, y, w, rank1, y, w), Error);
  EXPECT_THROW(LinearLeastSquaresPair::well_conditioned(0, 1), Error);
  EXPECT_THROW(LinearLeastSquaresPair::ill_conditioned(3, 1, 0.5), Error);
  auto p = LinearLeastSquaresPair::well_conditioned(3, 1);
  EXPECT_THROW(p.residuals(3, Eigen::VectorXd::Zero(3), false), Error);
  EXPECT_THROW(p.objectives(Eigen::VectorXd::Zero(2)), Error);
  EXPECT_THROW(p.weighted_sum_optimum(-1.0), Error);
  EXPECT_THROW(p.epsilon_constraint_optimum(-1.0), Error);

  const Eigen::VectorXd t = Eigen::VectorXd::LinSpaced(4, 0, 1);
  EXPECT_THROW(ExponentialDecayPair(t, Eigen::VectorXd::Ones(3), Eigen::VectorXd::Ones(4), t, t, t), Error);
  Eigen::VectorXd tnan = t;
  tnan(2) = INFINITY;
  EXPECT_THROW(ExponentialDecayPair(tnan, t, Eigen::VectorXd::Ones(4), t, t, Eigen::VectorXd::Ones(4)), Error);
  EXPECT_THROW(ExponentialDecayPair::synthetic(1, 1), Error);
  auto e = ExponentialDecayPair::synthetic(10, 1);
  EXPECT_THROW(e.residuals(1, Eigen::VectorXd::Zero(2), false), Error);
  EXPECT_THROW(e.weighted_sum_optimum(NAN), Error);
}
