#pragma once
// Analytic bi-objective instance: two weighted linear least-squares objectives in R^n,
//   F_j(x) = || A_j x - y_j ||^2_{W_j} = (A_j x - y_j)^T diag(w_j) (A_j x - y_j),  j = 1, 2.
// Its Pareto front is known in closed form, so it is the oracle of the solver tests:
//   * weighted sum (eq. `new weighted sum form`): x(lambda) is the least-squares solution of
//     the stacked system [W_1^{1/2} A_1; sqrt(lambda) W_2^{1/2} A_2] x = [W_1^{1/2} y_1; ...],
//     computed by Householder QR (never by the normal equations the backends use);
//   * epsilon-constraint (eq. `bounded objective form`): for epsilon between min F_2 and
//     F_2(argmin F_1) the optimum is x(mu) with F_2(x(mu)) = epsilon, found by bisection on
//     log mu over QR solutions (F_2(x(mu)) is decreasing in mu).
// Factories: well_conditioned (Gaussian A_j) and ill_conditioned (A_j = U diag(s) V^T with
// singular values log-spaced down to 1/condition).
#include <array>
#include <cstdint>
#include <string>

#include <Eigen/Core>

#include "solvers/problem.h"

namespace bivo::problems {

class LinearLeastSquaresPair final : public solvers::BiObjectiveProblem {
 public:
  // Throws bivo::Error on mismatched sizes, non-finite data, negative weights or a stacked
  // system without full column rank.
  LinearLeastSquaresPair(std::string name, Eigen::MatrixXd A1, Eigen::VectorXd y1, Eigen::VectorXd w1,
                         Eigen::MatrixXd A2, Eigen::VectorXd y2, Eigen::VectorXd w2);

  // n unknowns, m = 3n rows per objective; the two targets come from different x so the
  // objectives conflict.
  static LinearLeastSquaresPair well_conditioned(int n, std::uint64_t seed);
  static LinearLeastSquaresPair ill_conditioned(int n, std::uint64_t seed, double condition = 1e3);

  // BiObjectiveProblem
  std::string name() const override { return name_; }
  const solvers::Manifold& manifold() const override { return manifold_; }
  solvers::Linearization linearize(const Eigen::VectorXd& x, const solvers::LinearizeOptions& options) override;
  std::array<double, 2> evaluate(const Eigen::VectorXd& x) override { return objectives(x); }
  solvers::ResidualData residuals(int j, const Eigen::VectorXd& x, bool with_jacobian) override;

  int dim() const { return static_cast<int>(A1_.cols()); }
  std::array<double, 2> objectives(const Eigen::VectorXd& x) const;

  // ---- oracles ----
  Eigen::VectorXd weighted_sum_optimum(double lambda) const;  // lambda >= 0
  Eigen::VectorXd minimizer(int j) const;                     // argmin F_j (A_j full column rank)
  struct EpsilonOptimum {
    Eigen::VectorXd x;
    double mu = 0.0;  // multiplier of F_2 <= epsilon; +inf when infeasible
    bool feasible = true;
  };
  EpsilonOptimum epsilon_constraint_optimum(double epsilon) const;

 private:
  Eigen::VectorXd stacked_solve(double weight1, double weight2) const;

  std::string name_;
  Eigen::MatrixXd A1_, A2_;
  Eigen::VectorXd y1_, y2_, w1_, w2_;
  solvers::EuclideanManifold manifold_;
};

}  // namespace bivo::problems
