#pragma once
// Where a problem's unknown x lives and how a tangent step moves it: x (+) delta.
// Bodies in manifold.cpp: they instantiate Eigen decompositions, which would cost every file
// that includes this header (nearly all of them) seconds of compile time.
#include <Eigen/Core>

#include "solvers/error.h"
#include "solvers/geometry/se3.h"

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
  virtual Eigen::MatrixXd plus_jacobian(const Eigen::VectorXd& x) const;

  // The tangent delta with retract(x, delta) = y (inverse retraction). Default: Gauss-Newton
  // on retract with plus_jacobian at the moving point, valid for y near x.
  virtual Eigen::VectorXd minus(const Eigen::VectorXd& y, const Eigen::VectorXd& x) const;
};

class EuclideanManifold final : public Manifold {
 public:
  explicit EuclideanManifold(int n) : n_(n) {}
  int ambient_dim() const override { return n_; }
  int tangent_dim() const override { return n_; }
  Eigen::VectorXd retract(const Eigen::VectorXd& x, const Eigen::VectorXd& delta) const override;
  Eigen::MatrixXd plus_jacobian(const Eigen::VectorXd&) const override;
  Eigen::VectorXd minus(const Eigen::VectorXd& y, const Eigen::VectorXd& x) const override;

 private:
  int n_;
};

// Poses stored as [tx ty tz qx qy qz qw]; left perturbation exp(delta) * T, delta = [v; w].
class Se3Manifold final : public Manifold {
 public:
  int ambient_dim() const override { return 7; }
  int tangent_dim() const override { return 6; }
  Eigen::VectorXd retract(const Eigen::VectorXd& x, const Eigen::VectorXd& delta) const override;
  // exp(d) T at d = 0: t' = t + v + w x t, q' = [w/2; 1] (x) q (quaternion product), so
  // dt/dv = I, dt/dw = -[t]x, d q_vec/dw = (q_w I - [q_vec]x)/2, d q_w/dw = -q_vec^T/2.
  Eigen::MatrixXd plus_jacobian(const Eigen::VectorXd& x) const override;
  // log(T_y T_x^{-1}): the left perturbation that carries x to y.
  Eigen::VectorXd minus(const Eigen::VectorXd& y, const Eigen::VectorXd& x) const override;
};

}  // namespace bivo::solvers
