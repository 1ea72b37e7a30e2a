#include "solvers/problem.h"

#include <utility>

namespace bivo::solvers {

QuadraticModel quadratic_model_of(const ResidualData& d) {
  QuadraticModel m;
  const Eigen::VectorXd wr = d.w.cwiseProduct(d.r);
  m.a = d.r.dot(wr);
  m.b = d.J.transpose() * wr;
  m.H = d.J.transpose() * d.w.asDiagonal() * d.J;
  return m;
}

Linearization linearize_from_residuals(BiObjectiveProblem& problem, const Eigen::VectorXd& x,
                                       const LinearizeOptions& options) {
  ResidualData d1, d2;
  {
    ScopedPhase phase(options.profile, "residuals");
    d1 = problem.residuals(1, x, true);
    d2 = problem.residuals(2, x, true);
  }
  Linearization lin;
  {
    ScopedPhase phase(options.profile, "normal_equations");
    lin.f1 = quadratic_model_of(d1);
    lin.f2 = quadratic_model_of(d2);
  }
  if (options.want_full) {
    lin.full1 = std::move(d1);
    lin.full2 = std::move(d2);
  }
  return lin;
}

}  // namespace bivo::solvers
