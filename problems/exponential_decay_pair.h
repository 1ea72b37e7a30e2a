#pragma once
// Nonlinear bi-objective instance: two exponential-decay data sets that share one rate k,
//   r_1,i = c_1 exp(-k t_i) - y_1,i,   r_2,i = c_2 exp(-k t_i) - y_2,i,   x = [c_1, c_2, k],
// F_j = r_j^T diag(w_j) r_j. The data sets were generated with different rates, so the
// objectives conflict over k. Oracle for the weighted sum (variable projection): for fixed k
// the amplitudes are linear, c_j*(k) = sum w y e / sum w e^2 (e = exp(-k t)), and
// g(k) = F_1 + lambda F_2 at (c_1*(k), c_2*(k), k) has g'(k) = dF/dk (envelope theorem); the
// optimum is the root of g' found by a dense scan plus bisection to machine precision.
#include <array>
#include <cstdint>
#include <string>

#include <Eigen/Core>

#include "solvers/problem.h"

namespace bivo::problems {

class ExponentialDecayPair final : public solvers::BiObjectiveProblem {
 public:
  // Throws bivo::Error on mismatched sizes, non-finite data or negative weights.
  ExponentialDecayPair(Eigen::VectorXd t1, Eigen::VectorXd y1, Eigen::VectorXd w1, Eigen::VectorXd t2,
                       Eigen::VectorXd y2, Eigen::VectorXd w2);
  // m samples per set on t in [0, 4]; rates 0.7 and 1.4, amplitudes 2 and 5, noise sigma 0.02.
  static ExponentialDecayPair synthetic(int m, std::uint64_t seed);

  std::string name() const override { return "exponential-decay pair"; }
  const solvers::Manifold& manifold() const override { return manifold_; }
  solvers::Linearization linearize(const Eigen::VectorXd& x, const solvers::LinearizeOptions& options) override;
  std::array<double, 2> evaluate(const Eigen::VectorXd& x) override;
  solvers::ResidualData residuals(int j, const Eigen::VectorXd& x, bool with_jacobian) override;

  // Oracle: argmin F_1 + lambda F_2 over k in [k_lo, k_hi] (the global minimizer on that
  // interval; throws if it sits on the boundary).
  Eigen::VectorXd weighted_sum_optimum(double lambda, double k_lo = 0.05, double k_hi = 5.0) const;

 private:
  solvers::ResidualData residuals_of(int j, const Eigen::VectorXd& x, bool with_jacobian) const;
  double reduced_derivative(double k, double lambda, double* c1, double* c2) const;

  Eigen::VectorXd t1_, y1_, w1_, t2_, y2_, w2_;
  solvers::EuclideanManifold manifold_{3};
};

}  // namespace bivo::problems
