// Every exit of the conic IPM re-checked here, from the returned (x, y, z, s) and the data as
// given (tests/support/conic_exit_check.h: formulas written independently of the solver).
// The problems are the families the other conic tests solve (the same generators and seeds
// as test_conic_ipm's random SOCPs and certificates, the QCQP steps of the step backends in
// both forms, with and without polishing and equilibration) plus the huge-bound examples.
#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "solvers/conic/cones.h"
#include "solvers/conic/ipm_solver.h"
#include "solvers/step/qcqp_socp.h"
#include "tests/support/conic_exit_check.h"
#include "tests/support/random_conic.h"
#include "tests/support/synthetic_qcqp.h"

using namespace bivo::solvers::conic;
using namespace bivo::solvers::conic::testing;

namespace {

std::vector<IpmSettings> variants() {
  IpmSettings plain, unscaled, bare;
  plain.polish = false;
  unscaled.equilibration_passes = 0;
  bare.polish = false;
  bare.equilibration_passes = 0;
  return {IpmSettings{}, plain, unscaled, bare};
}

}  // namespace

// test_conic_ipm's 1000 random strictly feasible SOCPs (same generator, same seed), each in
// four settings: every optimum claimed must be one.
TEST(ConicExitCertificates, RandomFeasibleSocps) {
  RandomFeasibleSocps problems(2024);
  ExitTally t;
  for (int trial = 0; trial < 1000; ++trial) {
    const ConicProblem p = problems.next();
    int v = 0;
    for (const IpmSettings& st : variants()) {
      check_exit(p, solve_conic(p, st), "trial " + std::to_string(trial) + " variant " + std::to_string(v++), t);
    }
  }
  std::printf("random SOCPs: %d optimal, %d reduced accuracy, %d other\n", t.optimal, t.reduced, t.other);
  EXPECT_GE(t.optimal, 3900);  // the family is well posed: nearly every exit is a clean optimum
}

// test_conic_ipm's infeasible and unbounded families (same generators, same seeds).
TEST(ConicExitCertificates, InfeasibleAndUnboundedSocps) {
  ExitTally t;
  for (const bool dual : {false, true}) {
    std::mt19937 rng(dual ? 6 : 5);
    for (int trial = 0; trial < 100; ++trial) {
      const ConicProblem p = dual ? random_dual_infeasible_socp(trial, rng) : random_primal_infeasible_socp(trial, rng);
      const IpmResult r = solve_conic(p);
      EXPECT_EQ(r.status, dual ? IpmStatus::kDualInfeasible : IpmStatus::kPrimalInfeasible) << status_text(r);
      check_exit(p, r, std::string(dual ? "unbounded " : "infeasible ") + std::to_string(trial), t);
    }
  }
  EXPECT_EQ(t.infeasible, 200);
}

// The QCQP steps of ipm-full and ipm-compressed (synthetic image-like data in raw units), at
// the step backends' tolerances, polished and not.
TEST(ConicExitCertificates, QcqpStepForms) {
  ExitTally t;
  for (const std::uint32_t seed : {1u, 2u, 3u, 4u}) {
    for (const double fraction : {0.3, 2.0}) {
      const SyntheticStep step = make_synthetic_step(400 * static_cast<int>(seed), seed, fraction);
      const ConicProblem full = full_qcqp_socp(*step.lin.full1, *step.lin.full2, step.epsilon);
      const ConicProblem compressed =
          compressed_qcqp_socp(factor_from_model(step.lin.f1), factor_from_model(step.lin.f2), step.epsilon);
      for (const IpmSettings& st : {step_ipm_settings(), unpolished_step_ipm_settings()}) {
        const std::string what = "seed " + std::to_string(seed) + (st.polish ? " polished" : " plain");
        check_exit(full, solve_conic(full, st), "full form, " + what, t);
        check_exit(compressed, solve_conic(compressed, st), "compressed form, " + what, t);
      }
    }
  }
  std::printf("QCQP steps: %d optimal, %d reduced accuracy, %d other\n", t.optimal, t.reduced, t.other);
  EXPECT_GE(t.optimal, 24);
}

// The huge-bound examples: every exit, polished or not, presolved or not.
TEST(ConicExitCertificates, HugeBounds) {
  ExitTally t;
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(6, 3);
  G(0, 1) = 1, G(1, 2) = 1, G(2, 1) = -1;
  G(3, 0) = -1, G(4, 1) = -1, G(5, 2) = -1;
  for (const double B : {1e12, 1e15, 1e18, 1e19, 1e20, 1e30}) {
    ConicProblem p;
    p.c = Eigen::Vector3d(1, 0, 0);
    p.G = G.sparseView();
    p.h.resize(6);
    p.h << 1, B, B, 0, -3, -4;
    p.cones = {3, {3}};
    p.A.resize(0, 3);
    p.b.resize(0);
    for (IpmSettings st : variants()) {
      for (const double infinity : {1e20, std::numeric_limits<double>::infinity()}) {
        st.infinity = infinity;
        const IpmResult r = solve_conic(p, st);
        // Presolved rows are certified on the problem without them (their bound is absent).
        if (r.infinite_rows > 0) continue;
        check_exit(p, r, "bound " + std::to_string(B), t);
      }
    }
  }
  std::printf("huge bounds: %d optimal, %d reduced accuracy, %d other\n", t.optimal, t.reduced, t.other);
}
