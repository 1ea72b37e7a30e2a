#pragma once
// The exact step of the epsilon-constraint scalarization (eq. `QCQP`):
//   min_d m_1(d) = a_1 + 2 b_1^T d + d^T H_1 d   s.t.   m_2(d) = a_2 + 2 b_2^T d + d^T H_2 d <= epsilon
// with H_1, H_2 symmetric positive semidefinite. KKT: d(mu) = -(H_1 + mu H_2)^{-1}(b_1 + mu b_2),
// mu >= 0, mu (m_2(d) - epsilon) = 0. phi(mu) = m_2(d(mu)) is non-increasing, so
//   * phi(0+) <= epsilon        -> constraint inactive, mu = 0;
//   * phi(+inf) = min m_2 > eps -> infeasible: the m_2-minimizer (ties broken by m_1), mu = +inf;
//   * otherwise mu > 0 solves phi(mu) = epsilon (safeguarded Newton with bisection).
// Rank deficiency: directions in the common null space of H_1 + H_2 change neither model (for
// least-squares models b_j lies in range(H_j)); they are projected out, i.e. the minimum-norm
// step is returned. The limits mu -> 0+ and mu -> inf with singular H_1 or H_2 are the
// lexicographic minimizers (argmin m_1, then m_2 among those; and vice versa).
// Derivation and safeguards: docs/solvers.md, "The exact QCQP step".
#include <string>

#include <Eigen/Core>

#include "solvers/problem.h"
#include "solvers/step_backend.h"

namespace bivo::solvers {

struct ExactQcqpOptions {
  // |m_2(d) - epsilon| <= tol * max(epsilon, |min m_2|) ends the search on mu.
  double relative_tolerance = 1e-14;
  int max_iterations = 200;
  // Eigenvalues of (H_1 + H_2)/2 below this times the largest count as zero.
  double rank_tolerance = 1e-13;
};

struct ExactQcqpResult {
  Eigen::VectorXd delta;
  double mu = 0.0;  // +inf when infeasible
  bool feasible = true;
  bool active = false;        // constraint active (mu > 0)
  double m1 = 0.0, m2 = 0.0;  // model values at delta
  double min_m2 = 0.0;        // the model's minimum of m_2 (when computed: active or infeasible)
  int iterations = 0;         // evaluations of d(mu)
  std::string status;
};

// Throws bivo::Error on epsilon < 0 / NaN, size mismatch or non-finite models.
ExactQcqpResult solve_qcqp_exact(const QuadraticModel& m1, const QuadraticModel& m2, double epsilon,
                                 const ExactQcqpOptions& options = {});

class ExactQcqpBackend final : public StepBackend {
 public:
  explicit ExactQcqpBackend(ExactQcqpOptions options = {}) : options_(options) {}
  std::string name() const override { return "exact"; }
  bool supports(ScalarizationKind kind) const override { return kind == ScalarizationKind::kEpsilonConstraint; }
  StepResult solve(const Subproblem& subproblem) override;

 private:
  ExactQcqpOptions options_;
};

}  // namespace bivo::solvers
