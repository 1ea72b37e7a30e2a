// The conic IPM's fixed cost, by counts (no timing): the KKT pattern, ordering and symbolic
// factorization once per solve, one numeric factorization per iteration, and the polish's
// operations never more than the interior-point method's, so a rejected polish cannot
// dominate a solve (the Huber-fitting example of the CVXOPT book spent 98 % of its time in
// twelve rejected attempts). The answers are checked against closed-form optimality.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "solvers/conic/ipm_solver.h"
#include "tests/support/huber_fit.h"
#include "tests/support/random_conic.h"

using namespace bivo::solvers::conic;

namespace {

void expect_bounded_fixed_cost(const IpmResult& r) {
  EXPECT_EQ(r.timings.kkt_setups, 1);
  // The initial point's factorization and one per iteration taken (the last iterate's
  // verdict needs none).
  EXPECT_LE(r.timings.kkt_factors, r.iterations + 1);
  EXPECT_GT(r.timings.ipm_operations, 0.0);
  EXPECT_LE(r.timings.polish_operations, r.timings.ipm_operations);
  // At most one attempt per iterate, and the one at convergence.
  EXPECT_LE(r.timings.polish_attempts, r.iterations + 2);
}

// d/dr of the Huber penalty with threshold 1, as the SOCP writes it: r^2 inside, 2|r| - 1 outside.
double huber_slope(double r) { return std::abs(r) <= 1.0 ? 2.0 * r : (r > 0.0 ? 2.0 : -2.0); }
double huber(double r) { return std::abs(r) <= 1.0 ? r * r : 2.0 * std::abs(r) - 1.0; }

}  // namespace

// The fit's optimality in closed form: the gradient of sum_i huber(a + b u_i - y_i) is zero
// at (a, b), and the SOCP's objective is that sum.
TEST(ConicPolishBudget, HuberFitIsOptimalAndThePolishCostsLessThanTheIterations) {
  const ConicProblem p = bivo::solvers::conic::testing::huber_fit();
  const int m = 42;
  for (const bool polish : {true, false}) {
    IpmSettings st;
    st.polish = polish;
    const IpmResult r = solve_conic(p, st);
    ASSERT_EQ(r.status, IpmStatus::kOptimal) << "polish " << polish;
    expect_bounded_fixed_cost(r);
    if (!polish) {
      EXPECT_EQ(r.timings.polish_attempts, 0);
    }
    // The data again, from the problem's rows: +-(a + b u_i - y_i) <= w_i + v_i.
    double ga = 0.0, gb = 0.0, loss = 0.0;
    for (int i = 0; i < m; ++i) {
      const double u = p.G.coeff(2 * i, 1), y = p.h[2 * i];
      const double res = r.x[0] + r.x[1] * u - y;
      ga += huber_slope(res);
      gb += huber_slope(res) * u;
      loss += huber(res);
    }
    EXPECT_NEAR(loss, r.primal_objective, 1e-7 * (1.0 + loss)) << "polish " << polish;
    // Polished: to rounding; else as far as the IPM's tolerances (1e-8, relative) carry
    // through 42 residuals with |u| <= 10.
    const double tol = r.polished ? 1e-9 : 1e-4;
    EXPECT_NEAR(ga, 0.0, tol) << "polish " << polish;
    EXPECT_NEAR(gb, 0.0, 10.0 * tol) << "polish " << polish;
  }
}

// Random feasible SOCPs: every solve within the counts above, and the polished answer the
// unpolished one up to the tolerances.
TEST(ConicPolishBudget, RandomSocpsKeepTheCountsAndTheAnswers) {
  bivo::solvers::conic::testing::RandomFeasibleSocps gen(38);
  int polished = 0;
  for (int t = 0; t < 200; ++t) {
    const ConicProblem p = gen.next();
    IpmSettings with, without;
    without.polish = false;
    const IpmResult a = solve_conic(p, with), b = solve_conic(p, without);
    ASSERT_EQ(a.status, IpmStatus::kOptimal) << "problem " << t;
    ASSERT_EQ(b.status, IpmStatus::kOptimal) << "problem " << t;
    expect_bounded_fixed_cost(a);
    expect_bounded_fixed_cost(b);
    EXPECT_NEAR(a.primal_objective, b.primal_objective, 1e-6 * (1.0 + std::abs(b.primal_objective))) << "problem " << t;
    polished += a.polished ? 1 : 0;
  }
  // The budget must not starve the polish on small problems: most of them end polished.
  EXPECT_GE(polished, 150);
}
