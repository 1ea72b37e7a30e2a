#include "solvers/step/levenberg_marquardt.h"

#include <algorithm>

#include "solvers/error.h"
#include "solvers/step/symmetric_solve.h"

namespace bivo::solvers {

StepResult LevenbergMarquardtBackend::solve(const Subproblem& sp) {
  if (sp.kind != ScalarizationKind::kWeightedSum || sp.lin == nullptr) {
    throw Error("lm: needs a weighted-sum subproblem with a linearization");
  }
  const Linearization& lin = *sp.lin;
  Eigen::MatrixXd H = lin.f1.H + sp.lambda * lin.f2.H;
  const Eigen::VectorXd g = lin.f1.b + sp.lambda * lin.f2.b;
  // Marquardt's scaling makes the damping invariant to the units of each variable; the floor
  // keeps directions with a zero diagonal damped too.
  const Eigen::VectorXd diag = H.diagonal().cwiseAbs();
  const double floor = std::max(1e-12 * diag.maxCoeff(), 1e-300);
  for (Eigen::Index i = 0; i < H.rows(); ++i) H(i, i) += nu_ * std::max(diag(i), floor);
  const SymmetricSolve s = solve_symmetric_psd(H, -g);
  StepResult r;
  r.delta = s.x;
  r.multiplier = sp.lambda;
  r.iterations = 1;
  r.status = "damping " + std::to_string(nu_);
  return r;
}

void LevenbergMarquardtBackend::on_step_evaluated(bool accepted) {
  nu_ = accepted ? std::max(nu_ / 3.0, options_.min_damping) : std::min(nu_ * 4.0, options_.max_damping);
}

}  // namespace bivo::solvers
