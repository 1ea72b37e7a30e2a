#pragma once
// `nlopt`: NLopt's SLSQP on the epsilon-constraint step (eq. `QCQP`), in the scaled
// variables and functions of solvers/step/scaled_qcqp.h (SLSQP fails in raw units).
// Infeasible epsilon (below min m2, from the model's floor) is flagged without calling NLopt.
#include "solvers/step_backend.h"

namespace bivo::solvers {

class NloptSlsqpBackend final : public StepBackend {
 public:
  std::string name() const override { return "nlopt"; }
  bool supports(ScalarizationKind kind) const override { return kind == ScalarizationKind::kEpsilonConstraint; }
  StepResult solve(const Subproblem& subproblem) override;
};

}  // namespace bivo::solvers
