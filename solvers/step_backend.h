#pragma once
// One interface for every backend that solves the subproblem of one outer iteration.
#include <string>

#include <Eigen/Core>

#include "solvers/problem.h"

namespace bivo::solvers {

enum class ScalarizationKind { kWeightedSum, kEpsilonConstraint };

// The subproblem a scalarization makes from one linearization (models m_1, m_2 in d):
//  * weighted sum (eq. `new weighted sum form`, `linear system`):  min m_1 + lambda m_2
//  * epsilon-constraint (eq. `QCQP`):                              min m_1 s.t. m_2 <= epsilon
struct Subproblem {
  ScalarizationKind kind = ScalarizationKind::kWeightedSum;
  const Linearization* lin = nullptr;
  double lambda = 0.0;
  double epsilon = 0.0;
  PhaseProfile* profile = nullptr;  // where a backend may record its own phases, named
                                    // "subproblem/<phase>" (parts of "subproblem"); may be null
};

struct StepResult {
  Eigen::VectorXd delta;    // tangent step
  double multiplier = 0.0;  // lambda used (weighted sum) or mu (epsilon-constraint)
  bool feasible = true;     // false: epsilon < min m_2; delta is then m_2's minimizer
  int iterations = 0;       // the backend's inner iterations (IPM, Newton on mu, ...)
  std::string status;       // the backend's own word on how it ended
};

class StepBackend {
 public:
  virtual ~StepBackend() = default;
  virtual std::string name() const = 0;
  virtual bool supports(ScalarizationKind kind) const = 0;
  // Full-size backends (ipm-full) need Linearization::full1/full2.
  virtual bool needs_full_residuals() const { return false; }
  virtual StepResult solve(const Subproblem& subproblem) = 0;

  // Damped backends (Levenberg-Marquardt) learn from the outer loop's verdict.
  virtual void reset() {}
  virtual bool wants_acceptance_test() const { return false; }
  virtual void on_step_evaluated(bool /*accepted*/) {}
};

}  // namespace bivo::solvers
