#pragma once
// Random conic problems for the IPM's tests: a cone product, a point strictly inside it and a
// sparse matrix, all from one generator, so that tests replaying the same seed see the same
// problems.
#include <algorithm>
#include <random>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include "solvers/conic/cones.h"
#include "solvers/conic/problem_data.h"

namespace bivo::solvers::conic::testing {

// u in the interior of K, at least 0.05 from its boundary.
inline Eigen::VectorXd random_interior(const ConeProduct& K, std::mt19937& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::VectorXd u(K.dim());
  for (int i = 0; i < K.dim(); ++i) u[i] = g(rng);
  const double e = K.min_eigenvalue(u);
  std::uniform_real_distribution<double> margin(0.05, 1.0);
  K.add_identity(u, -e + margin(rng));
  return u;
}

inline SparseMatrix random_sparse(int rows, int cols, double density, std::mt19937& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(rows, cols);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j)
      if (u(rng) < density) M(i, j) = g(rng);
  return M.sparseView();
}

// 0-4 orthant rows and 0-3 second-order cones of dimension 1-6 (never empty).
inline ConeSpec random_cones(std::mt19937& rng) {
  std::uniform_int_distribution<int> l(0, 4), k(0, 3), d(1, 6);
  ConeSpec spec;
  spec.nonnegative = l(rng);
  const int nsoc = k(rng);
  for (int i = 0; i < nsoc; ++i) spec.soc.push_back(d(rng));
  if (spec.dim() == 0) spec.nonnegative = 1;
  return spec;
}

// Feasible, bounded SOCPs with a known interior primal-dual point: x0, y0 free, s0, z0 inside
// K, b = A x0, h = G x0 + s0, c = -(G'z0 + A'y0). 1-8 variables, 0-3 equalities. The same
// seed gives the same sequence of problems.
class RandomFeasibleSocps {
 public:
  explicit RandomFeasibleSocps(unsigned seed) : rng_(seed) {}
  ConicProblem next() {
    ConicProblem p;
    p.cones = random_cones(rng_);
    const ConeProduct K(p.cones);
    const int n = nvar_(rng_);
    std::uniform_int_distribution<int> neq(0, std::max(0, std::min(n - 1, 3)));
    const int np = neq(rng_);
    p.A = random_sparse(np, n, 0.8, rng_);
    p.G = random_sparse(K.dim(), n, 0.6, rng_);
    Eigen::VectorXd x0(n), y0(np);
    for (int i = 0; i < n; ++i) x0[i] = g_(rng_);
    for (int i = 0; i < np; ++i) y0[i] = g_(rng_);
    const Eigen::VectorXd s0 = random_interior(K, rng_), z0 = random_interior(K, rng_);
    p.b = p.A * x0;
    p.h = p.G * x0 + s0;
    p.c = -(p.G.transpose() * z0);
    if (np) p.c -= p.A.transpose() * y0;
    return p;
  }

 private:
  std::mt19937 rng_;
  std::uniform_int_distribution<int> nvar_{1, 8};
  std::normal_distribution<double> g_{0.0, 1.0};
};

// Primal infeasible SOCP number `trial` (1-6 variables, 0-1 equalities): (yb, zb), zb inside
// K, is made a certificate (A'yb + G'zb = 0, h'zb + b'yb = -1) and the dual is strictly
// feasible, so "primal infeasible" is the only right answer.
inline ConicProblem random_primal_infeasible_socp(int trial, std::mt19937& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  ConicProblem p;
  p.cones = random_cones(rng);
  const ConeProduct K(p.cones);
  const int n = 1 + trial % 6, np = trial % 2;
  Eigen::MatrixXd A = Eigen::MatrixXd(random_sparse(np, n, 1.0, rng));
  Eigen::MatrixXd G = Eigen::MatrixXd(random_sparse(K.dim(), n, 0.8, rng));
  const Eigen::VectorXd zb = random_interior(K, rng);
  Eigen::VectorXd yb(np), x0(n), h(K.dim());
  for (int i = 0; i < np; ++i) yb[i] = g(rng);
  for (int i = 0; i < n; ++i) x0[i] = g(rng);
  for (int i = 0; i < K.dim(); ++i) h[i] = g(rng);
  G -= zb * (G.transpose() * zb + A.transpose() * yb).transpose() / zb.squaredNorm();
  const Eigen::VectorXd b = A * x0;
  h -= zb * (h.dot(zb) + b.dot(yb) + 1.0) / zb.squaredNorm();
  p.A = A.sparseView();
  p.G = G.sparseView(1.0, 1e-12);  // rows cancelled to ~1e-17 become exact zeros
  p.b = b;
  p.h = h;
  const Eigen::VectorXd z1 = random_interior(K, rng);
  p.c = -(G.transpose() * z1);
  if (np) p.c -= A.transpose() * Eigen::VectorXd::NullaryExpr(np, [&]() { return g(rng); });
  return p;
}

// Dual infeasible (unbounded) SOCP number `trial` (2-6 variables, 0-1 equalities): a ray
// x0 + t d with A d = 0, -G d inside K and c'd = -1 is feasible and unbounded below.
inline ConicProblem random_dual_infeasible_socp(int trial, std::mt19937& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  ConicProblem p;
  p.cones = random_cones(rng);
  const ConeProduct K(p.cones);
  const int n = 2 + trial % 5, np = trial % 2;
  Eigen::MatrixXd A = Eigen::MatrixXd(random_sparse(np, n, 1.0, rng));
  Eigen::MatrixXd G = Eigen::MatrixXd(random_sparse(K.dim(), n, 0.8, rng));
  Eigen::VectorXd d(n), x0(n), c(n);
  for (int i = 0; i < n; ++i) d[i] = g(rng), x0[i] = g(rng), c[i] = g(rng);
  A -= (A * d) * d.transpose() / d.squaredNorm();
  const Eigen::VectorXd kb = random_interior(K, rng);
  G -= (G * d + kb) * d.transpose() / d.squaredNorm();
  c -= d * (c.dot(d) + 1.0) / d.squaredNorm();
  p.A = A.sparseView();
  p.G = G.sparseView(1.0, 0.0);
  p.b = A * x0;
  p.h = G * x0 + random_interior(K, rng);
  p.c = c;
  return p;
}

}  // namespace bivo::solvers::conic::testing
