#include "solvers/step/ipm_full_backend.h"

#include "solvers/error.h"
#include "solvers/step/qcqp_socp.h"

namespace bivo::solvers {

StepResult IpmFullBackend::solve(const Subproblem& sp) {
  if (sp.kind != ScalarizationKind::kEpsilonConstraint || sp.lin == nullptr) {
    throw Error("ipm-full: needs an epsilon-constraint subproblem with a linearization");
  }
  const Linearization& lin = *sp.lin;
  if (!lin.full1 || !lin.full2 || lin.full1->J.size() == 0 || lin.full2->J.size() == 0) {
    throw Error("ipm-full: the linearization has no full residuals/Jacobians (LinearizeOptions::want_full)");
  }
  const conic::QcqpConeStep s = conic::with_compressed_fallback(
      conic::solve_qcqp_full(*lin.full1, *lin.full2, lin.f2, sp.epsilon, settings_, workspace_), lin.f1, lin.f2,
      sp.epsilon, settings_);
  conic::record_phases(s.timings, sp.profile);
  return conic::to_step_result(s);
}

}  // namespace bivo::solvers
