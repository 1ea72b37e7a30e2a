#include "solvers/step/ipm_compressed_backend.h"

#include "solvers/error.h"
#include "solvers/step/qcqp_socp.h"

namespace bivo::solvers {

StepResult IpmCompressedBackend::solve(const Subproblem& sp) {
  if (sp.kind != ScalarizationKind::kEpsilonConstraint || sp.lin == nullptr) {
    throw Error("ipm-compressed: needs an epsilon-constraint subproblem with a linearization");
  }
  const Linearization& lin = *sp.lin;
  const bool full = lin.full1 && lin.full2 && lin.full1->J.size() > 0 && lin.full2->J.size() > 0;
  const conic::ConeFactor f1 = full ? conic::factor_from_residuals(*lin.full1) : conic::factor_from_model(lin.f1);
  const conic::ConeFactor f2 = full ? conic::factor_from_residuals(*lin.full2) : conic::factor_from_model(lin.f2);
  const conic::QcqpConeStep s = conic::solve_qcqp_compressed(f1, f2, lin.f2, sp.epsilon, settings_);
  conic::record_phases(s.timings, sp.profile);
  return conic::to_step_result(s);
}

}  // namespace bivo::solvers
