// The SOCP step backends against the exact one-constraint QCQP step of the bi-objective
// layer (solvers/step/exact_qcqp.h: Newton/bisection on mu, an independent method), on
// image-like synthetic steps in raw units; full and compressed forms against each other.
#include <cmath>

#include <gtest/gtest.h>

#include "tests/test_support.h"

#include "solvers/error.h"
#include "solvers/step/exact_qcqp.h"
#include "solvers/step/ipm_compressed_backend.h"
#include "solvers/step/ipm_full_backend.h"
#include "solvers/step/qcqp_socp.h"
#include "tests/support/synthetic_qcqp.h"

using namespace bivo::solvers;

using bivo::testing::eps_subproblem;

namespace {

double rel(const Eigen::VectorXd& a, const Eigen::VectorXd& b) { return (a - b).norm() / std::max(1e-12, b.norm()); }

}  // namespace

TEST(SocpBackends, IpmFullAndCompressedMatchExactStepInRawUnits) {
  for (int n : {300, 1200, 4800}) {
    for (std::uint32_t seed = 1; seed <= 4; ++seed) {
      const conic::SyntheticStep s = conic::make_synthetic_step(n, seed, 0.2 + 0.15 * seed);
      const ExactQcqpResult ex = solve_qcqp_exact(s.lin.f1, s.lin.f2, s.epsilon);
      ASSERT_TRUE(ex.feasible);
      ASSERT_TRUE(ex.active);
      IpmFullBackend full, full_plain(conic::unpolished_step_ipm_settings());
      IpmCompressedBackend comp;
      const StepResult rf = full.solve(eps_subproblem(s.lin, s.epsilon));
      const StepResult rp = full_plain.solve(eps_subproblem(s.lin, s.epsilon));
      const StepResult rc = comp.solve(eps_subproblem(s.lin, s.epsilon));
      Linearization models_only = s.lin;
      models_only.full1.reset();
      models_only.full2.reset();
      const StepResult rm = comp.solve(eps_subproblem(models_only, s.epsilon));
      // Step accuracy: every polished form meets the 1e-6 (measured ~1e-13: the
      // active-set Newton polish solves the optimality conditions to rounding). The full
      // form without polishing keeps the floor F_1(min) inside t = ||e1||, where d moves only
      // a ~1e-3 part of t^2, so a relative gap at the KKT-precision limit (~1e-11) leaves up
      // to ~5e-5 in d (measured; docs/conic.md). Objective values agree far tighter.
      const double step_tol[4] = {1e-6, 1e-6, 1e-6, 1e-4};
      const StepResult* results[4] = {&rf, &rc, &rm, &rp};
      EXPECT_NE(rf.status.find("polished"), std::string::npos) << rf.status;
      EXPECT_EQ(rp.status.find("polished"), std::string::npos) << rp.status;
      for (int k = 0; k < 4; ++k) {
        const StepResult* r = results[k];
        SCOPED_TRACE("n = " + std::to_string(n) + ", seed " + std::to_string(seed) + ", form " + std::to_string(k) +
                     ", status " + r->status);
        EXPECT_EQ(r->status.rfind("optimal", 0), 0u);
        EXPECT_TRUE(r->feasible);
        EXPECT_LT(rel(r->delta, ex.delta), step_tol[k]);
        EXPECT_NEAR(r->multiplier, ex.mu, 10 * step_tol[k] * ex.mu);
        // The constraint holds (active) and the objective is optimal, in model terms.
        EXPECT_LE(s.lin.f2.value(r->delta), s.epsilon * (1 + 1e-7));
        EXPECT_NEAR(s.lin.f1.value(r->delta), ex.m1, 1e-9 * ex.m1);
      }
      EXPECT_LT(rel(rf.delta, rc.delta), 1e-6);  // full and compressed: the same step
      EXPECT_LT(rel(rf.delta, rm.delta), 1e-6);
    }
  }
}

TEST(SocpBackends, InactiveConstraintGivesUnconstrainedMinimizerAndZeroMu) {
  const conic::SyntheticStep s = conic::make_synthetic_step(1200, 9, 0.3);
  const double eps = 2.0 * s.lin.f2.value(-s.lin.f1.H.ldlt().solve(s.lin.f1.b));  // slack
  const Eigen::VectorXd d1 = -s.lin.f1.H.ldlt().solve(s.lin.f1.b);
  IpmFullBackend full;
  IpmCompressedBackend comp;
  for (StepBackend* b : std::initializer_list<StepBackend*>{&full, &comp}) {
    const StepResult r = b->solve(eps_subproblem(s.lin, eps));
    EXPECT_LT(rel(r.delta, d1), 1e-6) << b->name();
    EXPECT_LT(r.multiplier, 1e-6) << b->name();
  }
}

TEST(SocpBackends, EpsilonBelowFloorIsInfeasibleNotNaN) {
  const conic::SyntheticStep s = conic::make_synthetic_step(1200, 3, 0.3);
  const ExactQcqpResult ex = solve_qcqp_exact(s.lin.f1, s.lin.f2, s.epsilon);
  const double eps = 0.5 * ex.min_m2;
  IpmFullBackend full;
  IpmCompressedBackend comp;
  const Eigen::VectorXd d2 = -s.lin.f2.H.ldlt().solve(s.lin.f2.b);
  for (StepBackend* b : std::initializer_list<StepBackend*>{&full, &comp}) {
    const StepResult r = b->solve(eps_subproblem(s.lin, eps));
    EXPECT_FALSE(r.feasible) << b->name();
    EXPECT_TRUE(r.delta.allFinite());
    EXPECT_LT(rel(r.delta, d2), 1e-6) << b->name();  // m2's minimizer
  }
}

TEST(SocpBackends, RankDeficientModelsWorkFromGramData) {
  // Objective 1 sees only translation (rotation columns zero): H1 singular.
  conic::SyntheticStep s = conic::make_synthetic_step(600, 5, 0.4);
  s.lin.full1->J.rightCols(3).setZero();
  s.lin.f1 = quadratic_model_of(*s.lin.full1);
  const ExactQcqpResult ex = solve_qcqp_exact(s.lin.f1, s.lin.f2, s.epsilon);
  Linearization models_only = s.lin;
  models_only.full1.reset();
  models_only.full2.reset();
  IpmCompressedBackend comp;
  const StepResult r = comp.solve(eps_subproblem(models_only, s.epsilon));
  ASSERT_TRUE(r.feasible);
  // Model values: the step itself is poorly determined along the directions H1 ignores.
  EXPECT_NEAR(s.lin.f1.value(r.delta), ex.m1, 1e-8 * ex.m1);
  EXPECT_LE(s.lin.f2.value(r.delta), s.epsilon * (1 + 1e-8));
}

TEST(SocpBackends, BadInputIsAnError) {
  conic::SyntheticStep s = conic::make_synthetic_step(100, 2, 0.3);
  IpmFullBackend full;
  EXPECT_THROW(full.solve(eps_subproblem(s.lin, std::nan(""))), bivo::Error);
  EXPECT_THROW(full.solve(eps_subproblem(s.lin, -1.0)), bivo::Error);
  Linearization no_full = s.lin;
  no_full.full1.reset();
  EXPECT_THROW(full.solve(eps_subproblem(no_full, s.epsilon)), bivo::Error);
  s.lin.full2->w[3] = -1.0;
  EXPECT_THROW(full.solve(eps_subproblem(s.lin, s.epsilon)), bivo::Error);
  Subproblem ws;
  ws.kind = ScalarizationKind::kWeightedSum;
  ws.lin = &s.lin;
  EXPECT_THROW(full.solve(ws), bivo::Error);
}
