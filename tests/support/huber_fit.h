#pragma once
// Huber fitting as an SOCP, the robust-regression example of the CVXOPT book (Boyd and
// Vandenberghe, fig. 6.5) by its recipe: a straight line through m points, m - 2 of them with
// noise and 2 outliers, fitted with the Huber penalty (quadratic for |r| <= 1, linear beyond).
// The penalty as in the book's QP, minimize w'w + 2 1'v s.t. -w - v <= A x - y <= w + v,
// 0 <= w <= 1, v >= 0, with w'w <= t as the second-order cone ||(2w, t - 1)|| <= t + 1.
// The noise is a fixed sequence (no random engine), so the problem is the same everywhere.
// Variables (a, b, w, v, t): 2 + 2m + 1; rows: 5m orthant rows and one cone of dimension m + 2.
#include <cmath>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "solvers/conic/problem_data.h"

namespace bivo::solvers::conic::testing {

inline ConicProblem huber_fit(int m = 42) {
  const int n = 2 + 2 * m + 1, w0 = 2, v0 = 2 + m, t = n - 1;
  Eigen::VectorXd u(m), y(m);
  for (int i = 0; i < m - 2; ++i) {
    u[i] = -10.0 + 20.0 * i / (m - 3);
    y[i] = 1.0 + 0.5 * u[i] + 0.8 * std::sin(7.3 * i + 0.4);
  }
  u[m - 2] = -9.5;
  y[m - 2] = 20.0;
  u[m - 1] = 9.0;
  y[m - 1] = -15.0;
  ConicProblem p;
  p.c = Eigen::VectorXd::Zero(n);
  p.c.segment(v0, m).setConstant(2.0);
  p.c[t] = 1.0;
  p.A.resize(0, n);
  p.b.resize(0);
  std::vector<Eigen::Triplet<double>> g;
  std::vector<double> h;
  auto row = [&](std::initializer_list<std::pair<int, double>> entries, double rhs) {
    const int r = static_cast<int>(h.size());
    for (const auto& e : entries) g.emplace_back(r, e.first, e.second);
    h.push_back(rhs);
  };
  for (int i = 0; i < m; ++i) {  // +-(a + b u_i - y_i) <= w_i + v_i
    row({{0, 1.0}, {1, u[i]}, {w0 + i, -1.0}, {v0 + i, -1.0}}, y[i]);
    row({{0, -1.0}, {1, -u[i]}, {w0 + i, -1.0}, {v0 + i, -1.0}}, -y[i]);
  }
  for (int i = 0; i < m; ++i) {  // 0 <= w_i <= 1, v_i >= 0
    row({{w0 + i, -1.0}}, 0.0);
    row({{w0 + i, 1.0}}, 1.0);
    row({{v0 + i, -1.0}}, 0.0);
  }
  p.cones.nonnegative = static_cast<int>(h.size());
  row({{t, -1.0}}, 1.0);  // (t + 1, 2w, t - 1) in the cone
  for (int i = 0; i < m; ++i) row({{w0 + i, -2.0}}, 0.0);
  row({{t, -1.0}}, -1.0);
  p.cones.soc = {m + 2};
  p.G.resize(static_cast<int>(h.size()), n);
  p.G.setFromTriplets(g.begin(), g.end());
  p.h = Eigen::Map<const Eigen::VectorXd>(h.data(), static_cast<Eigen::Index>(h.size()));
  return p;
}

}  // namespace bivo::solvers::conic::testing
