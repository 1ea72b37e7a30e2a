#include "tests/support/synthetic_qcqp.h"

#include <cmath>
#include <random>

#include <Eigen/Dense>

namespace bivo::solvers::conic {

namespace {

// t-distribution weights w_i = (nu + 1) / (nu + r_i^2 / sigma^2) with sigma^2 the fixed point
// of sigma^2 = mean over valid i of w_i r_i^2 (Kerl et al. 2013); invalid terms keep w = 0.
void t_distribution_weights(const Eigen::VectorXd& r, Eigen::VectorXd& w, double nu = 5.0) {
  double sum = 0.0;
  int valid = 0;
  for (Eigen::Index i = 0; i < r.size(); ++i) {
    if (w[i] > 0.0) {
      sum += r[i] * r[i];
      ++valid;
    }
  }
  if (valid == 0) return;
  double var = std::max(sum / valid, 1e-300);
  for (int it = 0; it < 50; ++it) {
    double acc = 0.0;
    for (Eigen::Index i = 0; i < r.size(); ++i) {
      if (w[i] > 0.0) acc += r[i] * r[i] * (nu + 1.0) / (nu + r[i] * r[i] / var);
    }
    const double next = std::max(acc / valid, 1e-300);
    const bool done = std::abs(next - var) <= 1e-9 * var;
    var = next;
    if (done) break;
  }
  for (Eigen::Index i = 0; i < r.size(); ++i) {
    if (w[i] > 0.0) w[i] = (nu + 1.0) / (nu + r[i] * r[i] / var);
  }
}

}  // namespace

SyntheticStep make_synthetic_step(int n, std::uint32_t seed, double active_fraction) {
  SyntheticStepOptions o;
  o.active_fraction = active_fraction;
  return make_synthetic_step(n, seed, o);
}

SyntheticStep make_paper_step(int width, int height, std::uint32_t seed, bool active) {
  SyntheticStepOptions o;
  o.width = width;
  o.height = height;
  o.invalid_fraction = 0.1;
  o.t_weights = true;
  o.active_fraction = active ? 0.3 : 2.0;
  return make_synthetic_step(width * height, seed, o);
}

SyntheticStep make_synthetic_step(int n, std::uint32_t seed, const SyntheticStepOptions& o) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const int width = o.width > 0 ? o.width : std::max(1, static_cast<int>(std::lround(std::sqrt(n * 4.0 / 3.0))));
  const double fx = 525.0, fy = 525.0;
  const double cx = 0.5 * width, cy = 0.5 * (o.height > 0 ? o.height : n / width);
  ResidualData f1, f2;
  f1.r.resize(n);
  f1.J.resize(n, 6);
  f1.w.resize(n);
  f2.r.resize(n);
  f2.J.resize(n, 6);
  f2.w.resize(n);
  for (int i = 0; i < n; ++i) {
    const double u = i % width, v = i / width;
    const double Z = 1.5 + 0.8 * std::sin(u / 7.0) * std::cos(v / 11.0) + 0.02 * g(rng);
    const double X = (u - cx) / fx * Z, Y = (v - cy) / fy * Z;
    Eigen::Matrix<double, 2, 3> dpi;
    dpi << fx / Z, 0, -fx * X / (Z * Z), 0, fy / Z, -fy * Y / (Z * Z);
    Eigen::Matrix<double, 3, 6> dP;  // d(exp(d) P)/dd = [I, -[P]x]
    dP << 1, 0, 0, 0, Z, -Y, 0, 1, 0, -Z, 0, X, 0, 0, 1, Y, -X, 0;
    if (u01(rng) < o.invalid_fraction) {  // invalid pixel: no depth / out of view
      f1.r[i] = f2.r[i] = 0.0;
      f1.J.row(i).setZero();
      f2.J.row(i).setZero();
      f1.w[i] = f2.w[i] = 0.0;
      continue;
    }
    const Eigen::Vector2d gI(30.0 * std::sin(0.31 * u + 1.7 * std::sin(0.13 * v)) + 8.0 * g(rng),
                             30.0 * std::cos(0.23 * v + 1.3 * std::cos(0.17 * u)) + 8.0 * g(rng));
    const Eigen::Vector2d gZ(0.01 * std::cos(u / 7.0) + 0.003 * g(rng), -0.01 * std::sin(v / 11.0) + 0.003 * g(rng));
    f1.J.row(i) = gI.transpose() * dpi * dP;
    f2.J.row(i) = gZ.transpose() * dpi * dP - dP.row(2);
    f1.r[i] = 12.0 * g(rng) + 5.0;
    f2.r[i] = 0.01 * Z * g(rng) + 0.004;
    f1.w[i] = 1.0;
    f2.w[i] = 1.0 / (0.01 * Z * 0.01 * Z);
    if (o.t_weights) {
      // Outliers (occlusions, specularities): 5 % of the terms, ten times the noise.
      if (u01(rng) < 0.05) f1.r[i] += 120.0 * g(rng);
      if (u01(rng) < 0.05) f2.r[i] += 0.1 * Z * g(rng);
      f2.w[i] = 1.0;  // set below from the t-distribution, in raw units
    }
  }
  if (o.t_weights) {
    t_distribution_weights(f1.r, f1.w);
    t_distribution_weights(f2.r, f2.w);
  }
  SyntheticStep s;
  s.lin.f1 = quadratic_model_of(f1);
  s.lin.f2 = quadratic_model_of(f2);
  s.lin.full1 = std::move(f1);
  s.lin.full2 = std::move(f2);
  // epsilon between min m2 and m2 at the unconstrained minimizer of m1 (active), or above it.
  const auto& m1 = s.lin.f1;
  const auto& m2 = s.lin.f2;
  const Eigen::VectorXd d1 = -m1.H.ldlt().solve(m1.b);
  const Eigen::VectorXd d2 = -m2.H.ldlt().solve(m2.b);
  const double floor2 = m2.value(d2), at_d1 = m2.value(d1);
  s.epsilon = floor2 + o.active_fraction * (at_d1 - floor2);
  return s;
}

}  // namespace bivo::solvers::conic
