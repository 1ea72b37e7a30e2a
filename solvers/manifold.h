#pragma once
// Where a problem's unknown x lives and how a tangent step moves it: x (+) delta.
#include <Eigen/Core>

#include "solvers/error.h"
#include "solvers/se3.h"

namespace bivo::solvers {

class Manifold {
 public:
  virtual ~Manifold() = default;
  virtual int ambient_dim() const = 0;  // size of the stored x
  virtual int tangent_dim() const = 0;  // size of delta, Jacobians and H
  virtual Eigen::VectorXd retract(const Eigen::VectorXd& x, const Eigen::VectorXd& delta) const = 0;

  // d retract(x, delta) / d delta at delta = 0 (ambient_dim x tangent_dim). Whole-problem
  // backends (Ceres) need it. Default: central differences of retract (step 1e-6); the
  // manifolds below override it with the closed form.
  virtual Eigen::MatrixXd plus_jacobian(const Eigen::VectorXd& x) const {
    const double h = 1e-6;
    Eigen::MatrixXd P(ambient_dim(), tangent_dim());
    for (int k = 0; k < tangent_dim(); ++k) {
      Eigen::VectorXd e = Eigen::VectorXd::Zero(tangent_dim());
      e(k) = h;
      P.col(k) = (retract(x, e) - retract(x, -e)) / (2.0 * h);
    }
    return P;
  }

  // The tangent delta with retract(x, delta) = y (inverse retraction). Default: Gauss-Newton
  // on retract with plus_jacobian at the moving point, valid for y near x.
  virtual Eigen::VectorXd minus(const Eigen::VectorXd& y, const Eigen::VectorXd& x) const {
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
};

class EuclideanManifold final : public Manifold {
 public:
  explicit EuclideanManifold(int n) : n_(n) {}
  int ambient_dim() const override { return n_; }
  int tangent_dim() const override { return n_; }
  Eigen::VectorXd retract(const Eigen::VectorXd& x, const Eigen::VectorXd& delta) const override {
    return x + delta;
  }
  Eigen::MatrixXd plus_jacobian(const Eigen::VectorXd&) const override {
    return Eigen::MatrixXd::Identity(n_, n_);
  }
  Eigen::VectorXd minus(const Eigen::VectorXd& y, const Eigen::VectorXd& x) const override {
    return y - x;
  }

 private:
  int n_;
};

// Poses stored as [tx ty tz qx qy qz qw]; left perturbation exp(delta) * T, delta = [v; w].
class Se3Manifold final : public Manifold {
 public:
  int ambient_dim() const override { return 7; }
  int tangent_dim() const override { return 6; }
  Eigen::VectorXd retract(const Eigen::VectorXd& x, const Eigen::VectorXd& delta) const override {
    return se3::to_ambient(se3::retract(se3::from_ambient(x), delta.head<6>()));
  }
  // exp(d) T at d = 0: t' = t + v + w x t, q' = [w/2; 1] (x) q (quaternion product), so
  // dt/dv = I, dt/dw = -[t]x, d q_vec/dw = (q_w I - [q_vec]x)/2, d q_w/dw = -q_vec^T/2.
  Eigen::MatrixXd plus_jacobian(const Eigen::VectorXd& x) const override {
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
  // log(T_y T_x^{-1}): the left perturbation that carries x to y.
  Eigen::VectorXd minus(const Eigen::VectorXd& y, const Eigen::VectorXd& x) const override {
    return se3::log(se3::from_ambient(y) * se3::from_ambient(x).inverse());
  }
};

}  // namespace bivo::solvers
