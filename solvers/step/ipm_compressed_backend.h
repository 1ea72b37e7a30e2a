#pragma once
// `ipm-compressed`: the epsilon-constraint step as an SOCP whose cones are compressed to
// dimension 7 (t or the radius, plus 6): each objective is factored as
// ||R d + c||^2 + floor (thin QR of W^{1/2}[J r] when full residuals are present, else an
// eigen-factorization of the quadratic model's Gram data H, b, a), the floor kept out of
// the cone (radius sqrt(epsilon - floor_2)). Same conic IPM as ipm-full.
#include "solvers/conic/ipm_solver.h"
#include "solvers/step/qcqp_socp.h"
#include "solvers/step_backend.h"

namespace bivo::solvers {

class IpmCompressedBackend final : public StepBackend {
 public:
  explicit IpmCompressedBackend(conic::IpmSettings settings = conic::step_ipm_settings()) : settings_(settings) {}
  // "ipm-compressed", or "ipm-compressed-nopolish" when the settings turn polishing off (the IPM alone).
  std::string name() const override { return settings_.polish ? "ipm-compressed" : "ipm-compressed-nopolish"; }
  bool supports(ScalarizationKind kind) const override { return kind == ScalarizationKind::kEpsilonConstraint; }
  StepResult solve(const Subproblem& subproblem) override;

 private:
  conic::IpmSettings settings_;
};

}  // namespace bivo::solvers
