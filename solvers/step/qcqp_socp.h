#pragma once
// The epsilon-constraint step (eq. `QCQP`) as a second-order cone program for the conic
// IPM, in two forms:
//   full (eq. `SOCP in our method`, exactly the paper's G and h): variables (t, d),
//     cones (t, W1^{1/2}(J1 d + r1)) and (sqrt(eps), W2^{1/2}(J2 d + r2)) of dimension n+1;
//   compressed: each objective m_j(d) = ||R_j d + c_j||^2 + rho_j^2 with R_j 6x6 from a thin
//     factorization of W_j^{1/2}[J_j r_j] (QR) or of its Gram matrix [[H, b], [b^T, a]]
//     (eigen-factorization of H, so rank-deficient models work); the floor rho_j^2 stays
//     out of the cone: (t, R1 d + c1) and (sqrt(eps - rho2^2), R2 d + c2), dimension 7.
// mu (the constraint's multiplier in grad m1 + mu grad m2 = 0) comes from the dual of
// the second cone: mu = z2_0 * ||e1|| / sqrt(eps_cone) (derivation in docs/conic.md).
#include <string>

#include <Eigen/Core>

#include "solvers/conic/ipm_solver.h"
#include "solvers/conic/problem_data.h"
#include "solvers/problem.h"
#include "solvers/step_backend.h"

namespace bivo::solvers::conic {

// Tolerances for steps: the cone objective is t = ||e1|| (the full form keeps the floor
// inside), so a relative gap g moves d by ~sqrt(g) in H-norm; 1e-8 would leave ~1e-5 in the
// step. Steps ask for gap 1e-11 relative, feasibility 1e-9 (the KKT solves of cones of
// dimension n+1 stop resolving residuals much below that).
IpmSettings step_ipm_settings();
// The same without polishing (polish.h): the interior-point iterations alone, as ECOS runs.
IpmSettings unpolished_step_ipm_settings();

// m(d) = ||R d + c||^2 + floor, floor = min_d m(d) >= 0.
struct ConeFactor {
  Eigen::MatrixXd R;
  Eigen::VectorXd c;
  double floor = 0.0;
};

ConeFactor factor_from_model(const QuadraticModel& model);
ConeFactor factor_from_residuals(const ResidualData& data);  // needs J

struct QcqpConeStep {
  Eigen::VectorXd delta;
  double mu = 0.0;
  bool feasible = true;
  int iterations = 0;
  IpmStatus ipm_status = IpmStatus::kOptimal;
  bool reduced_accuracy = false;
  bool polished = false;
  bool fallback = false;  // answered by the compressed form (with_compressed_fallback)
  IpmTimings timings;     // of the IPM calls (none when answered without one)
  std::string status;
  // A clean optimum: IPM exit optimal at the strict tolerances (or infeasible epsilon).
  bool clean() const { return !feasible || (ipm_status == IpmStatus::kOptimal && !reduced_accuracy); }
};

// Eq. `SOCP in our method` verbatim (rows of invalid terms included as zero rows).
ConicProblem full_qcqp_socp(const ResidualData& f1, const ResidualData& f2, double epsilon);
void full_qcqp_socp(const ResidualData& f1, const ResidualData& f2, double epsilon,
                    ConicProblem& out);  // in out's buffers

// What solve_qcqp_full allocates, kept from one step to the next (the full form's SOCP and
// the IPM's buffers, ipm_solver.h): a step backend keeps one, so a step of the same image
// size neither allocates nor page-faults on O(n) memory.
struct FullFormWorkspace {
  ConicProblem socp;
  IpmWorkspace ipm;
};
ConicProblem compressed_qcqp_socp(const ConeFactor& f1, const ConeFactor& f2, double epsilon);

// Both check feasibility first from m2's floor: epsilon <= floor -> infeasible, the step is
// m2's minimum-norm minimizer, mu = +inf, no IPM call. Throws bivo::Error on bad sizes,
// negative weights, non-finite data or epsilon < 0 / NaN.
QcqpConeStep solve_qcqp_full(const ResidualData& f1, const ResidualData& f2, const QuadraticModel& m2, double epsilon,
                             const IpmSettings& settings = step_ipm_settings());
QcqpConeStep solve_qcqp_full(const ResidualData& f1, const ResidualData& f2, const QuadraticModel& m2, double epsilon,
                             const IpmSettings& settings, FullFormWorkspace& workspace);
QcqpConeStep solve_qcqp_compressed(const ConeFactor& f1, const ConeFactor& f2, const QuadraticModel& m2, double epsilon,
                                   const IpmSettings& settings = step_ipm_settings());

// The full form's own answer is the exact step only when it is a clean polished optimum: the
// IPM alone leaves ~1e-5 in d (its cone objective keeps F_1's floor inside t), and at
// n ~ 3e5 the stopping test can sit below the dual residual's rounding floor. Any other
// feasible answer is replaced by the compressed form's solution of the same step from the
// models (m1, m2; microseconds), if that one is a clean optimum; the status names both
// answers, iterations and timings add up. With polishing off (the *-nopolish backends)
// the full form's answer is returned as it is.
QcqpConeStep with_compressed_fallback(QcqpConeStep full, const QuadraticModel& m1, const QuadraticModel& m2,
                                      double epsilon, const IpmSettings& settings);

// epsilon <= min m2: m2's minimum-norm minimizer, mu = +inf, flagged infeasible (every
// epsilon-constraint backend answers an infeasible bound this same way, without a solver call).
QcqpConeStep infeasible_step(const QuadraticModel& m2);

StepResult to_step_result(const QcqpConeStep& s);

}  // namespace bivo::solvers::conic
