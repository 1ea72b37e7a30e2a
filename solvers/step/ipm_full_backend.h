#pragma once
// `ipm-full`: the epsilon-constraint step solved exactly as the paper does (eq. `SOCP in
// our method`: two cones of dimension n+1 built from the full weighted residuals and
// Jacobians), by the project's own conic IPM. Reproduces table 3's SOCP column; needs
// Linearization::full1/full2.
#include "solvers/conic/ipm_solver.h"
#include "solvers/step/qcqp_socp.h"
#include "solvers/step_backend.h"

namespace bivo::solvers {

class IpmFullBackend final : public StepBackend {
 public:
  explicit IpmFullBackend(conic::IpmSettings settings = conic::step_ipm_settings()) : settings_(settings) {}
  // "ipm-full", or "ipm-full-nopolish" when the settings turn polishing off (the IPM alone).
  std::string name() const override { return settings_.polish ? "ipm-full" : "ipm-full-nopolish"; }
  bool supports(ScalarizationKind kind) const override { return kind == ScalarizationKind::kEpsilonConstraint; }
  bool needs_full_residuals() const override { return true; }
  // Throws bivo::Error for a weighted-sum subproblem or missing full residuals.
  StepResult solve(const Subproblem& subproblem) override;

 private:
  conic::IpmSettings settings_;
  conic::FullFormWorkspace workspace_;  // kept between steps: no O(n) allocation per step
};

}  // namespace bivo::solvers
