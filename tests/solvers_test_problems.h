#pragma once
// Small bi-objective problems the solver tests share: an IRLS instance whose fixed point has a
// closed form (weights frozen), and a wrapper that counts a solve's calls.
#include <cstdint>
#include <random>
#include <string>

#include <Eigen/Dense>

#include "solvers/problem.h"

namespace bivo::testing {

// Robust (IRLS) instance: F_j = sum_i w_ji r_ji^2, r_j = A_j x - y_j with outliers, weights
// re-estimated by linearize() as Cauchy weights w = 1 / (1 + (r / c)^2) at the current x.
// Its solution is the IRLS fixed point: x = argmin of the weighted sum with W(x) frozen.
class ReweightedLinearPair final : public solvers::BiObjectiveProblem {
 public:
  explicit ReweightedLinearPair(std::uint64_t seed) : manifold_(4) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> g(0.0, 1.0);
    for (int j = 0; j < 2; ++j) {
      A_[j].resize(30, 4);
      y_[j].resize(30);
      Eigen::Vector4d x_true(g(rng), g(rng), g(rng), g(rng));
      for (int i = 0; i < 30; ++i) {
        for (int k = 0; k < 4; ++k) A_[j](i, k) = g(rng);
        y_[j](i) = A_[j].row(i).dot(x_true) + 0.05 * g(rng) + (i % 7 == 0 ? 5.0 : 0.0);  // outliers
      }
      w_[j] = Eigen::VectorXd::Ones(30);
    }
  }
  std::string name() const override { return "re-weighted linear pair"; }
  const solvers::Manifold& manifold() const override { return manifold_; }
  Eigen::VectorXd cauchy_weights(int j, const Eigen::VectorXd& x) const {
    const Eigen::VectorXd r = A_[j] * x - y_[j];
    return (1.0 / (1.0 + (r.array() / 0.5).square())).matrix();
  }
  solvers::Linearization linearize(const Eigen::VectorXd& x, const solvers::LinearizeOptions& o) override {
    if (o.update_weights) {
      w_[0] = cauchy_weights(0, x);
      w_[1] = cauchy_weights(1, x);
    }
    solvers::Linearization lin;
    solvers::QuadraticModel* m[2] = {&lin.f1, &lin.f2};
    for (int j = 0; j < 2; ++j) {
      const Eigen::VectorXd r = A_[j] * x - y_[j];
      m[j]->a = r.dot(w_[j].cwiseProduct(r));
      m[j]->b = A_[j].transpose() * w_[j].cwiseProduct(r);
      m[j]->H = A_[j].transpose() * w_[j].asDiagonal() * A_[j];
    }
    return lin;
  }
  std::array<double, 2> evaluate(const Eigen::VectorXd& x) override {
    const auto d1 = residuals(1, x, false), d2 = residuals(2, x, false);
    return {d1.r.dot(d1.w.cwiseProduct(d1.r)), d2.r.dot(d2.w.cwiseProduct(d2.r))};
  }
  solvers::ResidualData residuals(int j, const Eigen::VectorXd& x, bool with_jacobian) override {
    solvers::ResidualData d;
    d.r = A_[j - 1] * x - y_[j - 1];
    d.w = w_[j - 1];
    if (with_jacobian) d.J = A_[j - 1];
    return d;
  }
  // Weighted-sum optimum with the weights frozen at those of x (QR, independent of the solvers).
  Eigen::VectorXd frozen_weight_optimum(const Eigen::VectorXd& x, double lambda) const {
    Eigen::MatrixXd S(60, 4);
    Eigen::VectorXd rhs(60);
    const Eigen::VectorXd s1 = cauchy_weights(0, x).cwiseSqrt(), s2 = (lambda * cauchy_weights(1, x)).cwiseSqrt();
    S << s1.asDiagonal() * A_[0], s2.asDiagonal() * A_[1];
    rhs << s1.cwiseProduct(y_[0]), s2.cwiseProduct(y_[1]);
    return S.colPivHouseholderQr().solve(rhs);
  }

 private:
  Eigen::MatrixXd A_[2];
  Eigen::VectorXd y_[2], w_[2];
  solvers::EuclideanManifold manifold_;
};

// Counts the calls a solve makes to the problem it wraps.
class Counting final : public solvers::BiObjectiveProblem {
 public:
  explicit Counting(solvers::BiObjectiveProblem& inner) : inner_(inner) {}
  std::string name() const override { return inner_.name(); }
  const solvers::Manifold& manifold() const override { return inner_.manifold(); }
  solvers::Linearization linearize(const Eigen::VectorXd& x, const solvers::LinearizeOptions& o) override {
    ++linearizations;
    return inner_.linearize(x, o);
  }
  std::array<double, 2> evaluate(const Eigen::VectorXd& x) override {
    ++evaluations;
    return inner_.evaluate(x);
  }
  std::array<double, 2> evaluate_only(const Eigen::VectorXd& x) override {
    ++evaluations_only;
    return inner_.evaluate(x);
  }
  solvers::ResidualData residuals(int j, const Eigen::VectorXd& x, bool J) override {
    return inner_.residuals(j, x, J);
  }
  int linearizations = 0, evaluations = 0, evaluations_only = 0;

 private:
  solvers::BiObjectiveProblem& inner_;
};

}  // namespace bivo::testing
