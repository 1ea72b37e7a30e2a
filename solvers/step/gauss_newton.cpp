#include "solvers/step/gauss_newton.h"

#include "solvers/error.h"
#include "solvers/step/symmetric_solve.h"

namespace bivo::solvers {

StepResult GaussNewtonBackend::solve(const Subproblem& sp) {
  if (sp.kind != ScalarizationKind::kWeightedSum || sp.lin == nullptr) {
    throw Error("gn: needs a weighted-sum subproblem with a linearization");
  }
  const Linearization& lin = *sp.lin;
  // eq. `linear system`: (H_1 + lambda H_2) d = -(b_1 + lambda b_2)
  const Eigen::MatrixXd H = lin.f1.H + sp.lambda * lin.f2.H;
  const Eigen::VectorXd g = lin.f1.b + sp.lambda * lin.f2.b;
  const SymmetricSolve s = solve_symmetric_psd(H, -g);
  StepResult r;
  r.delta = s.x;
  r.multiplier = sp.lambda;
  r.iterations = 1;
  r.status =
      s.rank_deficient ? "rank-deficient system, minimum-norm step (rank " + std::to_string(s.rank) + ")" : "LDL^T";
  return r;
}

}  // namespace bivo::solvers
