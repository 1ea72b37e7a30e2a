#include "solvers/step/ipm_full_backend.h"

#include "solvers/conic/qcqp_socp.h"
#include "solvers/error.h"

namespace bivo::solvers {

StepResult IpmFullBackend::solve(const Subproblem& sp) {
  if (sp.kind != ScalarizationKind::kEpsilonConstraint || sp.lin == nullptr) {
    throw Error("ipm-full: needs an epsilon-constraint subproblem with a linearization");
  }
  const Linearization& lin = *sp.lin;
  if (!lin.full1 || !lin.full2 || lin.full1->J.size() == 0 || lin.full2->J.size() == 0) {
    throw Error("ipm-full: the linearization has no full residuals/Jacobians (LinearizeOptions::want_full)");
  }
  conic::QcqpConeStep s = conic::solve_qcqp_full(*lin.full1, *lin.full2, lin.f2, sp.epsilon, settings_);
  conic::record_phases(s.timings, sp.profile);
  // The full form's own answer is the exact step only when polished (the IPM alone leaves
  // ~1e-5 in d: its cone objective keeps F_1's floor inside t) and clean. Otherwise (the
  // polish refused, or the stopping test unreachable in double precision at n ~ 3e5) the
  // same step comes from the compressed form of the models (microseconds), and the status
  // says so.
  const bool exact = s.ipm_status == conic::IpmStatus::kOptimal && s.polished && !s.reduced_accuracy;
  if (settings_.polish && s.feasible && !exact) {
    conic::QcqpConeStep c = conic::solve_qcqp_compressed(conic::factor_from_model(lin.f1), conic::factor_from_model(lin.f2),
                                                         lin.f2, sp.epsilon, settings_);
    conic::record_phases(c.timings, sp.profile);
    const std::string note = "full form " + s.status + "; compressed-form fallback " + c.status;
    if (c.feasible == s.feasible && c.ipm_status == conic::IpmStatus::kOptimal && !c.reduced_accuracy) {
      c.iterations += s.iterations;
      s = c;
    }
    s.status = note;
  }
  return conic::to_step_result(s);
}

}  // namespace bivo::solvers
