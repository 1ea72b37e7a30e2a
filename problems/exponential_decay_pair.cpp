#include "problems/exponential_decay_pair.h"

#include <cmath>
#include <random>
#include <sstream>

#include "solvers/error.h"

namespace bivo::problems {
namespace {

void check_set(const char* which, const Eigen::VectorXd& t, const Eigen::VectorXd& y, const Eigen::VectorXd& w) {
  std::ostringstream msg;
  if (t.size() == 0 || y.size() != t.size() || w.size() != t.size()) {
    msg << "exponential-decay pair: data set " << which << " has t, y, w of sizes " << t.size() << ", " << y.size()
        << ", " << w.size() << " (need equal, > 0)";
    throw Error(msg.str());
  }
  if (!t.allFinite() || !y.allFinite() || !w.allFinite()) {
    msg << "exponential-decay pair: data set " << which << " has NaN/Inf entries";
    throw Error(msg.str());
  }
  if (w.minCoeff() < 0.0) {
    msg << "exponential-decay pair: data set " << which << " has a negative weight " << w.minCoeff();
    throw Error(msg.str());
  }
}

}  // namespace

ExponentialDecayPair::ExponentialDecayPair(Eigen::VectorXd t1, Eigen::VectorXd y1, Eigen::VectorXd w1,
                                           Eigen::VectorXd t2, Eigen::VectorXd y2, Eigen::VectorXd w2)
    : t1_(std::move(t1)),
      y1_(std::move(y1)),
      w1_(std::move(w1)),
      t2_(std::move(t2)),
      y2_(std::move(y2)),
      w2_(std::move(w2)) {
  check_set("1", t1_, y1_, w1_);
  check_set("2", t2_, y2_, w2_);
}

ExponentialDecayPair ExponentialDecayPair::synthetic(int m, std::uint64_t seed) {
  if (m < 2) throw Error("exponential-decay pair: need m >= 2 samples per set, got " + std::to_string(m));
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.02);
  Eigen::VectorXd t = Eigen::VectorXd::LinSpaced(m, 0.0, 4.0);
  Eigen::VectorXd y1(m), y2(m);
  for (int i = 0; i < m; ++i) {
    y1(i) = 2.0 * std::exp(-0.7 * t(i)) + noise(rng);
    y2(i) = 5.0 * std::exp(-1.4 * t(i)) + noise(rng);
  }
  return ExponentialDecayPair(t, y1, Eigen::VectorXd::Ones(m), t, y2, Eigen::VectorXd::Ones(m));
}

solvers::ResidualData ExponentialDecayPair::residuals_of(int j, const Eigen::VectorXd& x, bool with_jacobian) const {
  if (j != 1 && j != 2) throw Error("exponential-decay pair: objective index must be 1 or 2, got " + std::to_string(j));
  if (x.size() != 3)
    throw Error("exponential-decay pair: x must be [c1, c2, k], got " + std::to_string(x.size()) + " entries");
  const Eigen::VectorXd& t = j == 1 ? t1_ : t2_;
  const double c = x(j - 1), k = x(2);
  const Eigen::VectorXd e = (-k * t.array()).exp().matrix();
  solvers::ResidualData d;
  d.r = c * e - (j == 1 ? y1_ : y2_);
  d.w = j == 1 ? w1_ : w2_;
  if (with_jacobian) {
    d.J = Eigen::MatrixXd::Zero(t.size(), 3);
    d.J.col(j - 1) = e;
    d.J.col(2) = -c * t.cwiseProduct(e);
  }
  return d;
}

solvers::ResidualData ExponentialDecayPair::residuals(int j, const Eigen::VectorXd& x, bool with_jacobian) {
  return residuals_of(j, x, with_jacobian);
}

std::array<double, 2> ExponentialDecayPair::evaluate(const Eigen::VectorXd& x) {
  const auto d1 = residuals_of(1, x, false), d2 = residuals_of(2, x, false);
  return {d1.r.dot(d1.w.cwiseProduct(d1.r)), d2.r.dot(d2.w.cwiseProduct(d2.r))};
}

solvers::Linearization ExponentialDecayPair::linearize(const Eigen::VectorXd& x,
                                                       const solvers::LinearizeOptions& options) {
  return solvers::linearize_from_residuals(*this, x, options);
}

// g'(k) for g(k) = min_{c1,c2} F_1 + lambda F_2 (envelope theorem: only the explicit k
// dependence counts at the optimal amplitudes). Also returns the amplitudes.
double ExponentialDecayPair::reduced_derivative(double k, double lambda, double* c1, double* c2) const {
  const auto part = [k](const Eigen::VectorXd& t, const Eigen::VectorXd& y, const Eigen::VectorXd& w, double* c) {
    const Eigen::VectorXd e = (-k * t.array()).exp().matrix();
    *c = w.cwiseProduct(y).dot(e) / w.cwiseProduct(e).dot(e);
    const Eigen::VectorXd r = *c * e - y;
    return -2.0 * *c * (w.cwiseProduct(r).cwiseProduct(t)).dot(e);
  };
  return part(t1_, y1_, w1_, c1) + lambda * part(t2_, y2_, w2_, c2);
}

Eigen::VectorXd ExponentialDecayPair::weighted_sum_optimum(double lambda, double k_lo, double k_hi) const {
  if (!std::isfinite(lambda) || lambda < 0.0) {
    std::ostringstream msg;
    msg << "weighted_sum_optimum: lambda must be finite and >= 0, got " << lambda;
    throw Error(msg.str());
  }
  const int grid = 4000;
  double best_g = INFINITY;
  int best_i = -1;
  const auto g_at = [&](double k) {
    double c1, c2;
    reduced_derivative(k, lambda, &c1, &c2);
    Eigen::VectorXd x(3);
    x << c1, c2, k;
    const auto d1 = residuals_of(1, x, false), d2 = residuals_of(2, x, false);
    return d1.r.dot(d1.w.cwiseProduct(d1.r)) + lambda * d2.r.dot(d2.w.cwiseProduct(d2.r));
  };
  const auto k_of = [&](int i) { return k_lo + (k_hi - k_lo) * double(i) / grid; };
  for (int i = 0; i <= grid; ++i) {
    const double g = g_at(k_of(i));
    if (g < best_g) {
      best_g = g;
      best_i = i;
    }
  }
  if (best_i <= 0 || best_i >= grid) {
    std::ostringstream msg;
    msg << "weighted_sum_optimum: the minimum over k lies on the boundary of [" << k_lo << ", " << k_hi << "]";
    throw Error(msg.str());
  }
  double lo = k_of(best_i - 1), hi = k_of(best_i + 1), c1, c2;
  // g' < 0 left of the minimizer, > 0 right of it: bisect on its sign to machine precision.
  for (int it = 0; it < 200 && hi - lo > 2e-16 * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    (reduced_derivative(mid, lambda, &c1, &c2) < 0.0 ? lo : hi) = mid;
  }
  const double k = 0.5 * (lo + hi);
  reduced_derivative(k, lambda, &c1, &c2);
  Eigen::VectorXd x(3);
  x << c1, c2, k;
  return x;
}

}  // namespace bivo::problems
