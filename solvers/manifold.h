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
};

class EuclideanManifold final : public Manifold {
 public:
  explicit EuclideanManifold(int n) : n_(n) {}
  int ambient_dim() const override { return n_; }
  int tangent_dim() const override { return n_; }
  Eigen::VectorXd retract(const Eigen::VectorXd& x, const Eigen::VectorXd& delta) const override {
    return x + delta;
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
};

}  // namespace bivo::solvers
