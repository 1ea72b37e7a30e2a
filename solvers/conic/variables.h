#pragma once
// Iterate of the homogeneous self-dual embedding: (x, y, z, s, tau, kappa). The solution
// of the original problem is (x, y, z, s) / tau; tau -> 0 with kappa > 0 certifies
// infeasibility.
#include <Eigen/Core>

namespace bivo::solvers::conic {

struct Variables {
  Eigen::VectorXd x, y, z, s;
  double tau = 1.0, kappa = 1.0;

  void resize(int n, int p, int m) {
    x = Eigen::VectorXd::Zero(n);
    y = Eigen::VectorXd::Zero(p);
    z = Eigen::VectorXd::Zero(m);
    s = Eigen::VectorXd::Zero(m);
  }
};

}  // namespace bivo::solvers::conic
