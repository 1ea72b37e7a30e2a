#pragma once
// Nonlinear bi-objective instance on SE(3): F_j(T) = sum_i |T p_ji - q_ji|^2 with
// q_1 = T_a p_1 and q_2 = T_b p_2 (plus noise), T_a != T_b, so the objectives pull towards
// different poses. x = [t; q] on solvers::Se3Manifold; tangent Jacobians for the left
// perturbation (d(exp(d) T p)/d d at d = 0 = [I, -hat(T p)]). Used to compare backends that
// must agree on a curved manifold (GN vs Ceres, exact step vs ipopt-nlp).
#include <array>
#include <cstdint>
#include <string>

#include <Eigen/Core>

#include "solvers/problem.h"

namespace bivo::problems {

class PointAlignmentPair final : public solvers::BiObjectiveProblem {
 public:
  // 15 points per objective around z = 3; T_a = exp(0.3 g), T_b = exp(log T_a + 0.05 g) with
  // g standard normal; point noise sigma 0.01. Deterministic from the seed.
  explicit PointAlignmentPair(std::uint64_t seed);

  std::string name() const override { return "SE(3) point alignment pair"; }
  const solvers::Manifold& manifold() const override { return manifold_; }
  solvers::ResidualData residuals(int j, const Eigen::VectorXd& x, bool with_jacobian) override;
  solvers::Linearization linearize(const Eigen::VectorXd& x, const solvers::LinearizeOptions& options) override;
  std::array<double, 2> evaluate(const Eigen::VectorXd& x) override;

 private:
  Eigen::Matrix3Xd p_[2], q_[2];
  solvers::Se3Manifold manifold_;
};

}  // namespace bivo::problems
