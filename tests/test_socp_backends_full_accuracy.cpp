// ipm-full step accuracy against the exact QCQP step as the IPM tolerances tighten, with and
// without the active-set polish: measures (printed) how close the paper's full form gets, and
// asserts the level each reliably reaches. Unpolished, the error stalls around 1e-5 whatever
// the tolerance; polished, it is at rounding level, also when the tolerances asked are below
// what double precision can certify (the stall exit then polishes its best iterate).
#include <cstdio>

#include <gtest/gtest.h>

#include "solvers/step/exact_qcqp.h"
#include "solvers/step/ipm_full_backend.h"
#include "tests/support/synthetic_qcqp.h"

using namespace bivo::solvers;

TEST(SocpBackendsFullAccuracy, TighterTolerancesAgainstTheExactStep) {
  for (int n : {300, 1200}) {
    for (std::uint32_t seed = 1; seed <= 3; ++seed) {
      const conic::SyntheticStep s = conic::make_synthetic_step(n, seed, 0.2 + 0.15 * seed);
      const ExactQcqpResult ex = solve_qcqp_exact(s.lin.f1, s.lin.f2, s.epsilon);
      for (double reltol : {1e-11, 1e-13, 1e-15}) {
        conic::IpmSettings st = conic::step_ipm_settings();
        st.reltol = reltol;
        st.feastol = std::min(st.feastol, 1e3 * reltol);
        st.max_iterations = 200;
        for (bool polish : {true, false}) {
          st.polish = polish;
          IpmFullBackend full(st);
          Subproblem sp;
          sp.kind = ScalarizationKind::kEpsilonConstraint;
          sp.lin = &s.lin;
          sp.epsilon = s.epsilon;
          const StepResult r = full.solve(sp);
          const double err = (r.delta - ex.delta).norm() / ex.delta.norm();
          std::printf("n %d seed %u reltol %.0e %s: |d - d_exact|/|d_exact| %.2e, iterations %d, %s\n", n, seed, reltol,
                      full.name().c_str(), err, r.iterations, r.status.c_str());
          EXPECT_TRUE(r.delta.allFinite());
          EXPECT_LT(err, polish ? 1e-10 : 1e-4);
        }
      }
    }
  }
}
