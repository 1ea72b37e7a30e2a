#include "solvers/step/scaled_qcqp.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "solvers/error.h"

namespace bivo::solvers::conic {

ScaledQcqp scale_qcqp(const QuadraticModel& m1, const QuadraticModel& m2, double epsilon) {
  const auto n = m1.b.size();
  if (m1.H.rows() != n || m1.H.cols() != n || m2.b.size() != n || m2.H.rows() != n || m2.H.cols() != n) {
    throw Error("qcqp: models of different sizes (b1 has " + std::to_string(n) + " entries, b2 " +
                std::to_string(m2.b.size()) + ")");
  }
  if (!m1.H.allFinite() || !m2.H.allFinite() || !m1.b.allFinite() || !m2.b.allFinite() || !std::isfinite(m1.a) ||
      !std::isfinite(m2.a)) {
    throw Error("qcqp: quadratic models have non-finite entries");
  }
  if (!(epsilon >= 0.0) || !std::isfinite(epsilon)) {
    throw Error("qcqp: epsilon must be finite and >= 0, got " + std::to_string(epsilon));
  }
  ScaledQcqp q;
  const Eigen::VectorXd diag = m1.H.diagonal() + m2.H.diagonal();
  const double dmax = std::max(diag.maxCoeff(), 1e-300);
  q.S.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) q.S[i] = 1.0 / std::sqrt(std::max(diag[i], 1e-12 * dmax));
  q.H1 = q.S.asDiagonal() * m1.H * q.S.asDiagonal();
  q.H2 = q.S.asDiagonal() * m2.H * q.S.asDiagonal();
  q.b1 = q.S.cwiseProduct(m1.b);
  q.b2 = q.S.cwiseProduct(m2.b);
  q.c2 = m2.a - epsilon;
  q.s1 = std::max({q.b1.norm(), q.H1.trace() / static_cast<double>(n), 1e-300});
  q.s2 = std::max({q.b2.norm(), q.H2.trace() / static_cast<double>(n), 1e-300});
  return q;
}

}  // namespace bivo::solvers::conic
