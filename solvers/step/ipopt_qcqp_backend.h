#pragma once
// `ipopt`: Ipopt (interior point, MUMPS) on the epsilon-constraint step (eq. `QCQP`) with
// exact Hessians, in the scaled variables of solvers/step/scaled_qcqp.h.
// bound_relax_factor = 0: Ipopt's default relaxes the constraint by 1e-8 * epsilon.
// mu is Ipopt's constraint multiplier mapped back to model units.
#include "solvers/step_backend.h"

namespace bivo::solvers {

class IpoptQcqpBackend final : public StepBackend {
 public:
  std::string name() const override { return "ipopt"; }
  bool supports(ScalarizationKind kind) const override { return kind == ScalarizationKind::kEpsilonConstraint; }
  StepResult solve(const Subproblem& subproblem) override;
};

}  // namespace bivo::solvers
