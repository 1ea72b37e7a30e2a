// Two paths of the ipm-full step that the default benchmark instances never take:
//  * the compressed-form fallback (with_compressed_fallback, qcqp_socp.h): a full-form answer
//    that is not a clean polished optimum is replaced by the compressed form's solution of
//    the same step; checked against the exact QCQP step (solve_qcqp_exact), and the exit
//    text and flags must say what happened (never "optimal" for an answer that is not);
//  * the solver workspace (IpmWorkspace, FullFormWorkspace): one workspace solving a mixed
//    sequence of problems (sizes, cone layouts, sparse and dense G, orthant, equalities,
//    infeasible) must give exactly what a fresh solve gives, problem by problem.
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "solvers/conic/ipm_solver.h"
#include "solvers/step/exact_qcqp.h"
#include "solvers/step/ipm_full_backend.h"
#include "solvers/step/qcqp_socp.h"
#include "tests/support/synthetic_qcqp.h"

using namespace bivo::solvers;

namespace {

double step_error(const Eigen::VectorXd& d, const Eigen::VectorXd& exact) { return (d - exact).norm() / exact.norm(); }

}  // namespace

TEST(SocpFallback, UnpolishedFullFormIsReplacedByTheCompressedFormsExactStep) {
  for (bool active : {true, false}) {
    const conic::SyntheticStep s = conic::make_paper_step(40, 30, 2, active);
    const Linearization& lin = s.lin;
    const Eigen::VectorXd exact = solve_qcqp_exact(lin.f1, lin.f2, s.epsilon).delta;
    // The full form without any polish (not during the iterations, not on a stall: with
    // polish_from = 0 alone the stall's polish made the step exact under clang -O1 and the
    // fallback went untested): the IPM alone, whose step is only ~1e-5 accurate
    // (docs/conic.md), so the fallback must answer.
    conic::IpmSettings no_polish_try = conic::step_ipm_settings();
    no_polish_try.polish = false;
    const conic::QcqpConeStep full = conic::solve_qcqp_full(*lin.full1, *lin.full2, lin.f2, s.epsilon, no_polish_try);
    ASSERT_TRUE(full.feasible);
    EXPECT_FALSE(full.polished && full.clean()) << full.status;
    const conic::QcqpConeStep r =
        conic::with_compressed_fallback(full, lin.f1, lin.f2, s.epsilon, conic::step_ipm_settings());
    EXPECT_TRUE(r.fallback) << r.status;
    EXPECT_TRUE(r.clean()) << r.status;
    EXPECT_EQ(r.ipm_status, conic::IpmStatus::kOptimal);
    EXPECT_LT(step_error(r.delta, exact), 1e-9) << r.status;
    // The status names both answers; iterations add up.
    EXPECT_EQ(r.status.rfind("full form " + full.status + "; compressed-form fallback optimal", 0), 0u) << r.status;
    EXPECT_GE(r.iterations, full.iterations);
    std::printf("%s: full form alone %.1e off the exact step (%s), after the fallback %.1e\n",
                active ? "active" : "inactive", step_error(full.delta, exact), full.status.c_str(),
                step_error(r.delta, exact));
    // Through the backend, with the polish not tried during the iterations (polish_from = 0;
    // its settings serve both forms): within the 1e-6 of the acceptance, and never an
    // unpolished full-form answer -- either the stall's polish answered (it does under clang
    // -O1) or the fallback did, and the status says which.
    conic::IpmSettings late_polish = conic::step_ipm_settings();
    late_polish.polish_from = 0.0;
    IpmFullBackend backend(late_polish);
    Subproblem sp;
    sp.kind = ScalarizationKind::kEpsilonConstraint;
    sp.lin = &lin;
    sp.epsilon = s.epsilon;
    const StepResult b = backend.solve(sp);
    EXPECT_LT(step_error(b.delta, exact), 1e-6) << b.status;
    EXPECT_TRUE(b.status.find("compressed-form fallback") != std::string::npos ||
                b.status.find("polished") != std::string::npos)
        << b.status;
  }
}

TEST(SocpFallback, AFailedFallbackKeepsTheFullFormsAnswerAndDoesNotClaimOptimal) {
  const conic::SyntheticStep s = conic::make_paper_step(40, 30, 1, true);
  const Linearization& lin = s.lin;
  // Both forms cut off early: three iterations of the full form, none of the compressed one,
  // no polish before the limit.
  conic::IpmSettings st = conic::step_ipm_settings();
  st.polish_from = 0.0;
  st.max_iterations = 3;
  const conic::QcqpConeStep full = conic::solve_qcqp_full(*lin.full1, *lin.full2, lin.f2, s.epsilon, st);
  ASSERT_EQ(full.ipm_status, conic::IpmStatus::kMaxIterations) << full.status;
  st.max_iterations = 0;
  const conic::QcqpConeStep r = conic::with_compressed_fallback(full, lin.f1, lin.f2, s.epsilon, st);
  EXPECT_FALSE(r.fallback);
  EXPECT_FALSE(r.clean());
  EXPECT_NE(r.ipm_status, conic::IpmStatus::kOptimal);
  EXPECT_EQ(r.delta, full.delta);  // the full form's own (inexact) answer, said to be so
  EXPECT_EQ(r.status.rfind("full form max iterations; compressed-form fallback max iterations", 0), 0u) << r.status;
  EXPECT_EQ(conic::to_step_result(r).status.find("optimal"), std::string::npos) << r.status;
}

TEST(IpmWorkspace, ReusedAcrossProblemsGivesExactlyTheFreshSolvesResults) {
  std::vector<conic::ConicProblem> problems;
  for (int width : {20, 40}) {
    for (bool active : {true, false}) {
      const conic::SyntheticStep s = conic::make_paper_step(width, width * 3 / 4, 3, active);
      problems.push_back(conic::full_qcqp_socp(*s.lin.full1, *s.lin.full2, s.epsilon));
      problems.push_back(conic::compressed_qcqp_socp(conic::factor_from_model(s.lin.f1),
                                                     conic::factor_from_model(s.lin.f2), s.epsilon));
    }
  }
  // min x1 + x2 + x3 s.t. x1 + x2 = 1, x >= 0 (orthant), ||(x2, x3)|| <= x1 + 1 (sparse G, an
  // equality), and an infeasible one (x >= 1 and x <= -1).
  conic::ConicProblem lp;
  lp.c = Eigen::Vector3d(1, 1, 1);
  Eigen::MatrixXd A(1, 3), G = Eigen::MatrixXd::Zero(6, 3);
  A << 1, 1, 0;
  lp.A = A.sparseView();
  lp.b = Eigen::VectorXd::Ones(1);
  G.topRows(3) = -Eigen::Matrix3d::Identity();
  G(3, 0) = -1;
  G(4, 1) = -1;
  G(5, 2) = -1;
  lp.G = G.sparseView();
  lp.h = Eigen::VectorXd::Zero(6);
  lp.h[3] = 1;
  lp.cones.nonnegative = 3;
  lp.cones.soc = {3};
  problems.push_back(lp);
  conic::ConicProblem infeasible;
  infeasible.c = Eigen::VectorXd::Ones(1);
  Eigen::MatrixXd Gi(2, 1);
  Gi << -1, 1;
  infeasible.G = Gi.sparseView();
  infeasible.h = Eigen::Vector2d(-1, -1);
  infeasible.cones.nonnegative = 2;
  problems.push_back(infeasible);
  problems.push_back(problems.front());  // back to the first size after the others

  conic::IpmWorkspace workspace;
  for (std::size_t i = 0; i < problems.size(); ++i) {
    // Every other solve without the polish: the workspace's polisher must then stay unused.
    const conic::IpmSettings st = i % 2 ? conic::unpolished_step_ipm_settings() : conic::step_ipm_settings();
    const conic::IpmResult fresh = conic::solve_conic(problems[i], st);
    const conic::IpmResult& reused = conic::solve_conic(problems[i], st, workspace);
    EXPECT_EQ(reused.status, fresh.status) << "problem " << i;
    EXPECT_EQ(reused.iterations, fresh.iterations) << "problem " << i;
    EXPECT_EQ(reused.polished, fresh.polished) << "problem " << i;
    EXPECT_EQ(reused.x, fresh.x) << "problem " << i;
    EXPECT_EQ(reused.z, fresh.z) << "problem " << i;
    EXPECT_EQ(reused.s, fresh.s) << "problem " << i;
    EXPECT_EQ(conic::status_text(reused), conic::status_text(fresh)) << "problem " << i;
  }
  EXPECT_EQ(conic::solve_conic(problems[problems.size() - 2], {}, workspace).status,
            conic::IpmStatus::kPrimalInfeasible);
}
