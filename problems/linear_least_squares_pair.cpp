#include "problems/linear_least_squares_pair.h"

#include <cmath>
#include <limits>
#include <random>
#include <sstream>

#include <Eigen/QR>

#include "solvers/error.h"

namespace bivo::problems {
namespace {

void check_block(const char* which, const Eigen::MatrixXd& A, const Eigen::VectorXd& y, const Eigen::VectorXd& w,
                 Eigen::Index n) {
  std::ostringstream msg;
  if (A.cols() != n || y.size() != A.rows() || w.size() != A.rows() || A.rows() == 0) {
    msg << "linear least-squares pair: objective " << which << " has A " << A.rows() << "x" << A.cols()
        << ", y of size " << y.size() << ", w of size " << w.size() << " (need A m x " << n
        << ", m > 0, y and w of size m)";
    throw Error(msg.str());
  }
  if (!A.allFinite() || !y.allFinite() || !w.allFinite()) {
    msg << "linear least-squares pair: objective " << which << " has NaN/Inf data";
    throw Error(msg.str());
  }
  if (w.minCoeff() < 0.0) {
    msg << "linear least-squares pair: objective " << which << " has a negative weight " << w.minCoeff();
    throw Error(msg.str());
  }
}

Eigen::MatrixXd gaussian(Eigen::Index rows, Eigen::Index cols, std::mt19937_64& rng) {
  std::normal_distribution<double> n01(0.0, 1.0);
  Eigen::MatrixXd M(rows, cols);
  for (Eigen::Index j = 0; j < cols; ++j)
    for (Eigen::Index i = 0; i < rows; ++i) M(i, j) = n01(rng);
  return M;
}

Eigen::VectorXd uniform_weights(Eigen::Index m, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.5, 2.0);
  Eigen::VectorXd w(m);
  for (Eigen::Index i = 0; i < m; ++i) w(i) = u(rng);
  return w;
}

// A = U diag(s) V^T with orthonormal U (m x n), V (n x n), s log-spaced from 1 to 1/condition.
Eigen::MatrixXd ill_conditioned_matrix(Eigen::Index m, Eigen::Index n, double condition, std::mt19937_64& rng) {
  const Eigen::MatrixXd U =
      Eigen::HouseholderQR<Eigen::MatrixXd>(gaussian(m, n, rng)).householderQ() * Eigen::MatrixXd::Identity(m, n);
  const Eigen::MatrixXd V =
      Eigen::HouseholderQR<Eigen::MatrixXd>(gaussian(n, n, rng)).householderQ() * Eigen::MatrixXd::Identity(n, n);
  Eigen::VectorXd s(n);
  for (Eigen::Index i = 0; i < n; ++i)
    s(i) = std::pow(condition, -double(i) / double(std::max<Eigen::Index>(n - 1, 1)));
  return U * s.asDiagonal() * V.transpose();
}

}  // namespace

LinearLeastSquaresPair::LinearLeastSquaresPair(std::string name, Eigen::MatrixXd A1, Eigen::VectorXd y1,
                                               Eigen::VectorXd w1, Eigen::MatrixXd A2, Eigen::VectorXd y2,
                                               Eigen::VectorXd w2)
    : name_(std::move(name)),
      A1_(std::move(A1)),
      A2_(std::move(A2)),
      y1_(std::move(y1)),
      y2_(std::move(y2)),
      w1_(std::move(w1)),
      w2_(std::move(w2)),
      manifold_(static_cast<int>(A1_.cols())) {
  if (A1_.cols() == 0) throw Error("linear least-squares pair: no unknowns (A_1 has 0 columns)");
  check_block("F_1", A1_, y1_, w1_, A1_.cols());
  check_block("F_2", A2_, y2_, w2_, A1_.cols());
  Eigen::MatrixXd stacked(A1_.rows() + A2_.rows(), A1_.cols());
  stacked << w1_.cwiseSqrt().asDiagonal() * A1_, w2_.cwiseSqrt().asDiagonal() * A2_;
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(stacked);
  if (qr.rank() < A1_.cols()) {
    std::ostringstream msg;
    msg << "linear least-squares pair '" << name_ << "': stacked system has rank " << qr.rank() << " < " << A1_.cols();
    throw Error(msg.str());
  }
}

LinearLeastSquaresPair LinearLeastSquaresPair::well_conditioned(int n, std::uint64_t seed) {
  if (n < 1) throw Error("linear least-squares pair: n must be >= 1, got " + std::to_string(n));
  std::mt19937_64 rng(seed);
  const Eigen::Index m = 3 * n;
  Eigen::MatrixXd A1 = gaussian(m, n, rng), A2 = gaussian(m, n, rng);
  const Eigen::VectorXd xa = gaussian(n, 1, rng), xb = gaussian(n, 1, rng);
  Eigen::VectorXd y1 = A1 * xa + 0.1 * gaussian(m, 1, rng).col(0);
  Eigen::VectorXd y2 = A2 * xb + 0.1 * gaussian(m, 1, rng).col(0);
  Eigen::VectorXd w1 = uniform_weights(m, rng), w2 = uniform_weights(m, rng);
  return LinearLeastSquaresPair("linear LS pair (well-conditioned, n=" + std::to_string(n) + ")", A1, y1, w1, A2, y2,
                                w2);
}

LinearLeastSquaresPair LinearLeastSquaresPair::ill_conditioned(int n, std::uint64_t seed, double condition) {
  if (n < 1) throw Error("linear least-squares pair: n must be >= 1, got " + std::to_string(n));
  if (!(condition >= 1.0) || !std::isfinite(condition)) {
    std::ostringstream msg;
    msg << "linear least-squares pair: condition must be finite and >= 1, got " << condition;
    throw Error(msg.str());
  }
  std::mt19937_64 rng(seed);
  const Eigen::Index m = 3 * n;
  Eigen::MatrixXd A1 = ill_conditioned_matrix(m, n, condition, rng);
  Eigen::MatrixXd A2 = ill_conditioned_matrix(m, n, std::sqrt(condition), rng);
  const Eigen::VectorXd xa = gaussian(n, 1, rng), xb = gaussian(n, 1, rng);
  Eigen::VectorXd y1 = A1 * xa + 0.01 * gaussian(m, 1, rng).col(0);
  Eigen::VectorXd y2 = A2 * xb + 0.01 * gaussian(m, 1, rng).col(0);
  Eigen::VectorXd w1 = uniform_weights(m, rng), w2 = uniform_weights(m, rng);
  std::ostringstream name;
  name << "linear LS pair (ill-conditioned, cond(A1)=" << condition << ", n=" << n << ")";
  return LinearLeastSquaresPair(name.str(), A1, y1, w1, A2, y2, w2);
}

std::array<double, 2> LinearLeastSquaresPair::objectives(const Eigen::VectorXd& x) const {
  if (x.size() != A1_.cols()) {
    throw Error("linear least-squares pair: x has " + std::to_string(x.size()) + " entries, expected " +
                std::to_string(A1_.cols()));
  }
  const Eigen::VectorXd r1 = A1_ * x - y1_, r2 = A2_ * x - y2_;
  return {r1.dot(w1_.cwiseProduct(r1)), r2.dot(w2_.cwiseProduct(r2))};
}

solvers::ResidualData LinearLeastSquaresPair::residuals(int j, const Eigen::VectorXd& x, bool with_jacobian) {
  if (j != 1 && j != 2)
    throw Error("linear least-squares pair: objective index must be 1 or 2, got " + std::to_string(j));
  if (x.size() != A1_.cols()) {
    throw Error("linear least-squares pair: x has " + std::to_string(x.size()) + " entries, expected " +
                std::to_string(A1_.cols()));
  }
  const Eigen::MatrixXd& A = j == 1 ? A1_ : A2_;
  solvers::ResidualData d;
  d.r = A * x - (j == 1 ? y1_ : y2_);
  d.w = j == 1 ? w1_ : w2_;
  if (with_jacobian) d.J = A;
  return d;
}

solvers::Linearization LinearLeastSquaresPair::linearize(const Eigen::VectorXd& x,
                                                         const solvers::LinearizeOptions& options) {
  return solvers::linearize_from_residuals(*this, x, options);
}

Eigen::VectorXd LinearLeastSquaresPair::stacked_solve(double weight1, double weight2) const {
  Eigen::MatrixXd S(A1_.rows() + A2_.rows(), A1_.cols());
  Eigen::VectorXd rhs(S.rows());
  const Eigen::VectorXd s1 = (weight1 * w1_).cwiseSqrt(), s2 = (weight2 * w2_).cwiseSqrt();
  S << s1.asDiagonal() * A1_, s2.asDiagonal() * A2_;
  rhs << s1.cwiseProduct(y1_), s2.cwiseProduct(y2_);
  return S.colPivHouseholderQr().solve(rhs);
}

Eigen::VectorXd LinearLeastSquaresPair::weighted_sum_optimum(double lambda) const {
  if (!std::isfinite(lambda) || lambda < 0.0) {
    std::ostringstream msg;
    msg << "weighted_sum_optimum: lambda must be finite and >= 0, got " << lambda;
    throw Error(msg.str());
  }
  return stacked_solve(1.0, lambda);
}

Eigen::VectorXd LinearLeastSquaresPair::minimizer(int j) const {
  if (j != 1 && j != 2) throw Error("minimizer: objective index must be 1 or 2, got " + std::to_string(j));
  return j == 1 ? stacked_solve(1.0, 0.0) : stacked_solve(0.0, 1.0);
}

LinearLeastSquaresPair::EpsilonOptimum LinearLeastSquaresPair::epsilon_constraint_optimum(double epsilon) const {
  if (!std::isfinite(epsilon) || epsilon < 0.0) {
    std::ostringstream msg;
    msg << "epsilon_constraint_optimum: epsilon must be finite and >= 0, got " << epsilon;
    throw Error(msg.str());
  }
  EpsilonOptimum out;
  out.x = minimizer(1);
  if (objectives(out.x)[1] <= epsilon) return out;  // constraint inactive
  const Eigen::VectorXd x2 = minimizer(2);
  if (epsilon < objectives(x2)[1]) {
    out.x = x2;
    out.mu = std::numeric_limits<double>::infinity();
    out.feasible = false;
    return out;
  }
  // Bracket mu* in [lo, hi] with F_2(x(lo)) > epsilon >= F_2(x(hi)), then bisect on log mu.
  const auto f2_at = [&](double mu) { return objectives(weighted_sum_optimum(mu))[1]; };
  double lo = 1.0, hi = 1.0;
  if (f2_at(1.0) > epsilon) {
    while (f2_at(hi) > epsilon) {
      lo = hi;
      hi *= 10.0;
      if (hi > 1e300) throw Error("epsilon_constraint_optimum: no finite multiplier reaches epsilon");
    }
  } else {
    while (f2_at(lo) <= epsilon) {
      hi = lo;
      lo /= 10.0;
      if (lo < 1e-300) break;
    }
  }
  for (int it = 0; it < 400 && hi > lo * (1.0 + 4.0 * std::numeric_limits<double>::epsilon()); ++it) {
    const double mid = std::sqrt(lo * hi);
    if (mid <= lo || mid >= hi) break;
    (f2_at(mid) > epsilon ? lo : hi) = mid;
  }
  out.mu = hi;
  out.x = weighted_sum_optimum(hi);
  return out;
}

}  // namespace bivo::problems
