#include "solvers/geometry/manifold.h"

#include <Eigen/QR>

namespace bivo::solvers {

Eigen::MatrixXd Manifold::plus_jacobian(const Eigen::VectorXd& x) const {
  const double h = 1e-6;
  Eigen::MatrixXd P(ambient_dim(), tangent_dim());
  for (int k = 0; k < tangent_dim(); ++k) {
    Eigen::VectorXd e = Eigen::VectorXd::Zero(tangent_dim());
    e(k) = h;
    P.col(k) = (retract(x, e) - retract(x, -e)) / (2.0 * h);
  }
  return P;
}

Eigen::VectorXd Manifold::minus(const Eigen::VectorXd& y, const Eigen::VectorXd& x) const {
  Eigen::VectorXd delta = Eigen::VectorXd::Zero(tangent_dim());
  for (int it = 0; it < 20; ++it) {
    const Eigen::VectorXd z = retract(x, delta);
    const Eigen::MatrixXd P = plus_jacobian(z);
    const Eigen::VectorXd step = P.completeOrthogonalDecomposition().solve(y - z);
    delta += step;
    if (step.norm() <= 1e-15 * (1.0 + delta.norm())) break;
  }
  return delta;
}

Eigen::VectorXd EuclideanManifold::retract(const Eigen::VectorXd& x, const Eigen::VectorXd& delta) const {
  return x + delta;
}

Eigen::MatrixXd EuclideanManifold::plus_jacobian(const Eigen::VectorXd&) const {
  return Eigen::MatrixXd::Identity(n_, n_);
}

Eigen::VectorXd EuclideanManifold::minus(const Eigen::VectorXd& y, const Eigen::VectorXd& x) const { return y - x; }

Eigen::VectorXd Se3Manifold::retract(const Eigen::VectorXd& x, const Eigen::VectorXd& delta) const {
  return se3::to_ambient(se3::retract(se3::from_ambient(x), delta.head<6>()));
}

Eigen::MatrixXd Se3Manifold::plus_jacobian(const Eigen::VectorXd& x) const {
  const Eigen::Vector3d t = x.head<3>();
  Eigen::Quaterniond q(x(6), x(3), x(4), x(5));
  q.normalize();
  Eigen::MatrixXd P = Eigen::MatrixXd::Zero(7, 6);
  P.block<3, 3>(0, 0).setIdentity();
  P.block<3, 3>(0, 3) = -se3::hat(t);
  P.block<3, 3>(3, 3) = 0.5 * (q.w() * Eigen::Matrix3d::Identity() - se3::hat(q.vec()));
  P.block<1, 3>(6, 3) = -0.5 * q.vec().transpose();
  return P;
}

Eigen::VectorXd Se3Manifold::minus(const Eigen::VectorXd& y, const Eigen::VectorXd& x) const {
  return se3::log(se3::from_ambient(y) * se3::from_ambient(x).inverse());
}

}  // namespace bivo::solvers
