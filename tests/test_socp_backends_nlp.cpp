// Ipopt and NLopt SLSQP on QCQP steps against the exact step (solvers/step/exact_qcqp.h),
// in raw units, within 1e-5.
#include <cmath>

#include <gtest/gtest.h>

#include "tests/test_support.h"

#include "solvers/error.h"
#include "solvers/step/exact_qcqp.h"
#include "solvers/step/ipopt_qcqp_backend.h"
#include "solvers/step/nlopt_slsqp_backend.h"
#include "tests/support/synthetic_qcqp.h"

using namespace bivo::solvers;

using bivo::testing::eps_subproblem;

TEST(NlpStepBackends, IpoptAndNloptMatchExactStepInRawUnits) {
  IpoptQcqpBackend ipopt;
  NloptSlsqpBackend nlopt;
  for (int n : {1200, 4800}) {
    for (std::uint32_t seed = 1; seed <= 3; ++seed) {
      const conic::SyntheticStep s = conic::make_synthetic_step(n, seed, 0.25 + 0.2 * seed);
      const ExactQcqpResult ex = solve_qcqp_exact(s.lin.f1, s.lin.f2, s.epsilon);
      for (StepBackend* b : std::initializer_list<StepBackend*>{&ipopt, &nlopt}) {
        const StepResult r = b->solve(eps_subproblem(s.lin, s.epsilon));
        SCOPED_TRACE(b->name() + " n = " + std::to_string(n) + " seed " + std::to_string(seed) + ": " + r.status);
        EXPECT_LT((r.delta - ex.delta).norm(), 1e-5 * ex.delta.norm());
        EXPECT_NEAR(r.multiplier, ex.mu, 1e-4 * ex.mu);
        EXPECT_LE(s.lin.f2.value(r.delta), s.epsilon * (1 + 1e-9));  // bound_relax_factor = 0
      }
    }
  }
}

TEST(NlpStepBackends, InfeasibleEpsilonIsFlagged) {
  const conic::SyntheticStep s = conic::make_synthetic_step(1200, 4, 0.3);
  const ExactQcqpResult ex = solve_qcqp_exact(s.lin.f1, s.lin.f2, s.epsilon);
  IpoptQcqpBackend ipopt;
  NloptSlsqpBackend nlopt;
  for (StepBackend* b : std::initializer_list<StepBackend*>{&ipopt, &nlopt}) {
    const StepResult r = b->solve(eps_subproblem(s.lin, 0.9 * ex.min_m2));
    EXPECT_FALSE(r.feasible) << b->name();
    EXPECT_TRUE(r.delta.allFinite()) << b->name();
    EXPECT_THROW(b->solve(eps_subproblem(s.lin, std::nan(""))), bivo::Error) << b->name();
  }
}
