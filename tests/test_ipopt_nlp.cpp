// "ipopt-nlp" (Ipopt on the whole nonlinear epsilon-constraint problem over the manifold)
// against independent oracles: the QR/bisection closed form of the linear pairs, the
// exact-step outer loop on the nonlinear exponential-decay pair and on an SE(3) alignment
// pair (with the KKT check x = argmin F1 + mu F2 on the former), and the failure paths.
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include <gtest/gtest.h>
#include <Eigen/Dense>

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

using bivo::testing::rel_err;

namespace {

solvers::SolverOptions tight_options() {
  solvers::SolverOptions opt;
  opt.max_iterations = 200;
  opt.relative_decrease_tolerance = 1e-20;
  opt.step_tolerance = 1e-12;
  return opt;
}

}  // namespace

TEST(IpoptNlp, IsRegisteredAsWholeProblemEpsilonBackend) {
  ASSERT_TRUE(solvers::has_backend("ipopt-nlp"));
  const auto& info = solvers::backend_info("ipopt-nlp");
  EXPECT_TRUE(info.whole_problem);
  EXPECT_TRUE(info.epsilon_constraint);
  EXPECT_FALSE(info.weighted_sum);
}

TEST(IpoptNlp, MatchesTheClosedFormEpsilonOptimumOnLinearPairs) {
  std::mt19937_64 rng(11);
  for (int draw = 0; draw < 8; ++draw) {
    auto p = draw % 2 ? LinearLeastSquaresPair::ill_conditioned(6, rng(), 1e3)
                      : LinearLeastSquaresPair::well_conditioned(6, rng());
    const double lo = p.objectives(p.minimizer(2))[1], hi = p.objectives(p.minimizer(1))[1];
    for (double frac : {0.1, 0.5, 0.9}) {
      const double eps = lo + frac * (hi - lo);
      const auto oracle = p.epsilon_constraint_optimum(eps);
      Eigen::VectorXd x = Eigen::VectorXd::Zero(6);
      const auto s = solvers::solve(p, solvers::EpsilonConstraint(eps), "ipopt-nlp", x, tight_options());
      SCOPED_TRACE(p.name() + " draw " + std::to_string(draw) + " frac " + std::to_string(frac) + "\n" +
                   s.FullReport());
      EXPECT_TRUE(s.converged());
      EXPECT_TRUE(s.feasible);
      EXPECT_LT(rel_err(x, oracle.x), 1e-5);
      std::printf("linear draw %d frac %.1f: |x - x*| rel %.2e, mu rel %.2e, rounds %zu, Ipopt its %d\n", draw, frac,
                  rel_err(x, oracle.x), std::abs(s.multiplier - oracle.mu) / oracle.mu, s.records.size(), s.iterations);
      EXPECT_NEAR(s.multiplier, oracle.mu, 1e-5 * oracle.mu);
      EXPECT_LE(s.final_f2, eps * (1 + 1e-9));   // bound_relax_factor = 0
      EXPECT_NEAR(s.final_f2, eps, 1e-6 * eps);  // the constraint is active for eps < F2(argmin F1)
    }
  }
}

TEST(IpoptNlp, InactiveConstraintGivesTheUnconstrainedMinimizer) {
  auto p = LinearLeastSquaresPair::well_conditioned(5, 3);
  const double hi = p.objectives(p.minimizer(1))[1];
  Eigen::VectorXd x = Eigen::VectorXd::Zero(5);
  const auto s = solvers::solve(p, solvers::EpsilonConstraint(2.0 * hi), "ipopt-nlp", x, tight_options());
  EXPECT_TRUE(s.feasible) << s.FullReport();
  EXPECT_LT(rel_err(x, p.minimizer(1)), 1e-6) << s.FullReport();
  EXPECT_LT(s.multiplier, 1e-6) << s.FullReport();
}

TEST(IpoptNlp, AgreesWithTheExactStepOuterLoopOnTheNonlinearPair) {
  auto p = ExponentialDecayPair::synthetic(60, 17);
  const double f2_hi = p.evaluate(p.weighted_sum_optimum(0.0))[1];
  const double f2_lo = p.evaluate(p.weighted_sum_optimum(1e6))[1];
  for (double frac : {0.05, 0.2, 0.6}) {
    const double eps = f2_lo + frac * (f2_hi - f2_lo);
    Eigen::VectorXd x_exact = Eigen::Vector3d(1.0, 1.0, 1.0), x = x_exact;
    const auto a = solvers::solve(p, solvers::EpsilonConstraint(eps), "exact", x_exact, tight_options());
    ASSERT_TRUE(a.converged()) << a.FullReport();
    const auto s = solvers::solve(p, solvers::EpsilonConstraint(eps), "ipopt-nlp", x, tight_options());
    SCOPED_TRACE("frac " + std::to_string(frac) + "\n" + s.FullReport());
    EXPECT_TRUE(s.converged());
    EXPECT_TRUE(s.feasible);
    EXPECT_LT(rel_err(x, x_exact), 1e-5);
    std::printf("exp-decay frac %.2f: |x - x_exact| rel %.2e, mu rel %.2e, rounds %zu\n", frac, rel_err(x, x_exact),
                std::abs(s.multiplier - a.multiplier) / a.multiplier, s.records.size());
    EXPECT_NEAR(s.multiplier, a.multiplier, 1e-4 * a.multiplier);
    EXPECT_LE(s.final_f2, eps * (1 + 1e-9));
    // KKT of eq. `bounded objective form`, from the variable-projection oracle.
    EXPECT_LT(rel_err(x, p.weighted_sum_optimum(s.multiplier)), 1e-5);
  }
}

TEST(IpoptNlp, AgreesWithTheExactStepOuterLoopOnSe3) {
  PointAlignmentPair p(4);
  const Eigen::VectorXd x0 = solvers::se3::to_ambient(Eigen::Isometry3d::Identity());
  // The two single-objective minimizers bracket the useful epsilon range.
  Eigen::VectorXd x1 = x0, x2 = x0;
  solvers::solve(p, solvers::WeightedSum(0.0), "gn", x1, tight_options());
  solvers::solve(p, solvers::WeightedSum(1e8), "gn", x2, tight_options());
  const double f2_hi = p.evaluate(x1)[1], f2_lo = p.evaluate(x2)[1];
  ASSERT_GT(f2_hi, 2.0 * f2_lo);
  for (double frac : {0.1, 0.5}) {
    const double eps = f2_lo + frac * (f2_hi - f2_lo);
    Eigen::VectorXd x_exact = x0, x = x0;
    const auto a = solvers::solve(p, solvers::EpsilonConstraint(eps), "exact", x_exact, tight_options());
    ASSERT_TRUE(a.converged()) << a.FullReport();
    const auto s = solvers::solve(p, solvers::EpsilonConstraint(eps), "ipopt-nlp", x, tight_options());
    SCOPED_TRACE("frac " + std::to_string(frac) + "\n" + s.FullReport());
    EXPECT_TRUE(s.converged());
    EXPECT_TRUE(s.feasible);
    const auto Ta = solvers::se3::from_ambient(x_exact), Tb = solvers::se3::from_ambient(x);
    EXPECT_LT(solvers::se3::log(Ta * Tb.inverse()).norm(), 1e-5);
    std::printf("SE(3) frac %.1f: |log(T_exact T^-1)| %.2e, mu rel %.2e, rounds %zu\n", frac,
                solvers::se3::log(Ta * Tb.inverse()).norm(), std::abs(s.multiplier - a.multiplier) / a.multiplier,
                s.records.size());
    EXPECT_NEAR(s.multiplier, a.multiplier, 1e-4 * a.multiplier);
    EXPECT_LE(s.final_f2, eps * (1 + 1e-9));
  }
}

TEST(IpoptNlp, InfeasibleEpsilonIsReportedNeverNaN) {
  auto p = ExponentialDecayPair::synthetic(40, 2);
  const double f2_lo = p.evaluate(p.weighted_sum_optimum(1e6))[1];
  Eigen::VectorXd x = Eigen::Vector3d(1.0, 1.0, 1.0);
  const auto s = solvers::solve(p, solvers::EpsilonConstraint(0.5 * f2_lo), "ipopt-nlp", x, tight_options());
  EXPECT_FALSE(s.feasible) << s.FullReport();
  EXPECT_EQ(s.termination, solvers::TerminationReason::kBackendFailure) << s.FullReport();
  EXPECT_NE(s.message.find("epsilon infeasible"), std::string::npos) << s.message;
  EXPECT_TRUE(std::isinf(s.multiplier));
  EXPECT_TRUE(x.allFinite());
  EXPECT_TRUE(std::isfinite(s.final_f1) && std::isfinite(s.final_f2));

  auto lin = LinearLeastSquaresPair::well_conditioned(4, 9);
  const double lo = lin.objectives(lin.minimizer(2))[1];
  Eigen::VectorXd y = Eigen::VectorXd::Zero(4);
  const auto t = solvers::solve(lin, solvers::EpsilonConstraint(0.5 * lo), "ipopt-nlp", y, tight_options());
  EXPECT_FALSE(t.feasible) << t.FullReport();
  EXPECT_TRUE(y.allFinite());
  // Ipopt's point of least violation is kept: F_2 there is (close to) min F_2.
  EXPECT_NEAR(t.final_f2, lo, 1e-4 * lo) << t.FullReport();
}

TEST(IpoptNlp, RejectsWrongScalarizationAndBadStart) {
  auto p = LinearLeastSquaresPair::well_conditioned(3, 1);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(3);
  EXPECT_THROW(solvers::solve(p, solvers::WeightedSum(1.0), "ipopt-nlp", x), Error);
  Eigen::VectorXd bad = Eigen::VectorXd::Zero(2);
  EXPECT_THROW(solvers::solve(p, solvers::EpsilonConstraint(1.0), "ipopt-nlp", bad), Error);
  Eigen::VectorXd nan = Eigen::VectorXd::Constant(3, std::nan(""));
  EXPECT_THROW(solvers::solve(p, solvers::EpsilonConstraint(1.0), "ipopt-nlp", nan), Error);
}
