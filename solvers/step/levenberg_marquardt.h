#pragma once
// Levenberg-Marquardt step of the weighted sum: with H = H_1 + lambda H_2, g = b_1 + lambda b_2,
//   (H + nu D) d = -g,   D = diag(H) floored at 1e-12 max diag(H)   (Marquardt's scaling).
// The outer loop runs the acceptance test: accepted -> nu /= 3 (at most down to nu_min),
// rejected -> nu *= 4 and the same linearization is solved again.
#include <string>

#include "solvers/step_backend.h"

namespace bivo::solvers {

struct LevenbergMarquardtOptions {
  double initial_damping = 1e-4;
  double min_damping = 1e-12;
  double max_damping = 1e12;
};

class LevenbergMarquardtBackend final : public StepBackend {
 public:
  explicit LevenbergMarquardtBackend(LevenbergMarquardtOptions options = {})
      : options_(options), nu_(options.initial_damping) {}
  std::string name() const override { return "lm"; }
  bool supports(ScalarizationKind kind) const override { return kind == ScalarizationKind::kWeightedSum; }
  StepResult solve(const Subproblem& subproblem) override;
  void reset() override { nu_ = options_.initial_damping; }
  bool wants_acceptance_test() const override { return true; }
  void on_step_evaluated(bool accepted) override;
  double damping() const { return nu_; }

 private:
  LevenbergMarquardtOptions options_;
  double nu_;
};

}  // namespace bivo::solvers
