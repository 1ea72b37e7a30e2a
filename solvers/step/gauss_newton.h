#pragma once
// Gauss-Newton step of the weighted sum (eq. `linear system`):
//   (H_1 + lambda H_2) d = -(b_1 + lambda b_2).
// Solved by LDL^T; a rank-deficient or numerically singular matrix falls back to the
// minimum-norm (pseudo-inverse) solution (solvers/step/symmetric_solve.h).
#include <string>

#include "solvers/step_backend.h"

namespace bivo::solvers {

class GaussNewtonBackend final : public StepBackend {
 public:
  std::string name() const override { return "gn"; }
  bool supports(ScalarizationKind kind) const override { return kind == ScalarizationKind::kWeightedSum; }
  StepResult solve(const Subproblem& subproblem) override;
};

}  // namespace bivo::solvers
