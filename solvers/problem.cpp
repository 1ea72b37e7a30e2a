#include "solvers/problem.h"

namespace bivo::solvers {

QuadraticModel quadratic_model_of(const ResidualData& d) {
  QuadraticModel m;
  const Eigen::VectorXd wr = d.w.cwiseProduct(d.r);
  m.a = d.r.dot(wr);
  m.b = d.J.transpose() * wr;
  m.H = d.J.transpose() * d.w.asDiagonal() * d.J;
  return m;
}

}  // namespace bivo::solvers
