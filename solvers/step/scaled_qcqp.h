#pragma once
// The QCQP step (eq. `QCQP`) in scaled variables and functions, for the general NLP
// solvers (Ipopt, NLopt SLSQP) that fail on raw units (H entries ~1e8 for intensity,
// translation vs rotation columns 1e2 apart):
//   d = S y,  S = diag(1 / sqrt(diag(H1 + H2))),
//   f(y) = (2 b1~^T y + y^T H1~ y) / s1,   g(y) = (a2 - eps + 2 b2~^T y + y^T H2~ y) / s2 <= 0,
// with Hj~ = S Hj S, bj~ = S bj and sj = max(||bj~||, tr(Hj~)/dim). A multiplier lambda of g
// maps back to mu = lambda s1 / s2.
#include <Eigen/Core>

#include "solvers/problem.h"

namespace bivo::solvers::conic {

struct ScaledQcqp {
  Eigen::VectorXd S;       // d = S .* y
  Eigen::MatrixXd H1, H2;  // scaled
  Eigen::VectorXd b1, b2;
  double c2 = 0.0;  // a2 - eps
  double s1 = 1.0, s2 = 1.0;

  int dim() const { return static_cast<int>(S.size()); }
  double f(const Eigen::VectorXd& y) const { return (2.0 * b1.dot(y) + y.dot(H1 * y)) / s1; }
  double g(const Eigen::VectorXd& y) const { return (c2 + 2.0 * b2.dot(y) + y.dot(H2 * y)) / s2; }
  Eigen::VectorXd grad_f(const Eigen::VectorXd& y) const { return 2.0 * (b1 + H1 * y) / s1; }
  Eigen::VectorXd grad_g(const Eigen::VectorXd& y) const { return 2.0 * (b2 + H2 * y) / s2; }
  Eigen::VectorXd to_delta(const Eigen::VectorXd& y) const { return S.cwiseProduct(y); }
  double to_mu(double lambda) const { return lambda * s1 / s2; }
};

// Throws bivo::Error on size mismatch, non-finite models or epsilon < 0 / NaN.
ScaledQcqp scale_qcqp(const QuadraticModel& m1, const QuadraticModel& m2, double epsilon);

}  // namespace bivo::solvers::conic
