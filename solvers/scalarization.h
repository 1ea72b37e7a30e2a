#pragma once
// Scalarizations turn one Linearization (both quadratic models m_1, m_2 at the current x)
// into the Subproblem a StepBackend solves:
//   WeightedSum        (eq. `new weighted sum form`):  min F_1 + lambda F_2, lambda >= 0;
//                      per step the linear system of eq. `linear system`.
//   EpsilonConstraint  (eq. `bounded objective form`): min F_1 s.t. F_2 <= epsilon, epsilon >= 0;
//                      per step the QCQP of eq. `QCQP`.
// lambda / epsilon are either fixed or chosen per linearization by a policy (the odometry
// layer's adaptive lambda of eq. `eq to calculate lambda`, or an epsilon rule). A policy is
// called once per outer iteration, with the linearization the step will be built from.
// Negative or non-finite lambda / epsilon (fixed or returned by a policy) -> bivo::Error
// naming the value.
//
// Which backends accept which scalarization (see solvers/backend_registry.h):
//   weighted sum:        gn, lm, ceres (whole problem)
//   epsilon-constraint:  exact, ipm-full, ipm-compressed, ipopt, nlopt, ipopt-nlp (whole problem)
#include <functional>
#include <memory>
#include <string>

#include "solvers/problem.h"
#include "solvers/step_backend.h"

namespace bivo::solvers {

using LambdaPolicy = std::function<double(const Linearization&)>;
using EpsilonPolicy = std::function<double(const Linearization&)>;

class Scalarization {
 public:
  virtual ~Scalarization() = default;
  virtual ScalarizationKind kind() const = 0;
  // "weighted sum (lambda = 0.5)", "epsilon-constraint (epsilon from policy)", ...
  virtual std::string describe() const = 0;
  // The subproblem of one outer iteration; `lin` must outlive the returned Subproblem.
  // Validates the models (sizes agree, all entries finite) and the parameter.
  virtual Subproblem make_subproblem(const Linearization& lin) const = 0;
  virtual std::unique_ptr<Scalarization> clone() const = 0;
};

class WeightedSum final : public Scalarization {
 public:
  explicit WeightedSum(double lambda);        // throws on lambda < 0 or non-finite
  explicit WeightedSum(LambdaPolicy policy);  // throws on an empty policy
  ScalarizationKind kind() const override { return ScalarizationKind::kWeightedSum; }
  std::string describe() const override;
  Subproblem make_subproblem(const Linearization& lin) const override;
  std::unique_ptr<Scalarization> clone() const override;

  bool has_policy() const { return static_cast<bool>(policy_); }
  double fixed_lambda() const { return lambda_; }     // meaningful when !has_policy()
  double lambda_for(const Linearization& lin) const;  // validated value for this step

 private:
  double lambda_ = 0.0;
  LambdaPolicy policy_;
};

class EpsilonConstraint final : public Scalarization {
 public:
  explicit EpsilonConstraint(double epsilon);        // throws on epsilon < 0 or non-finite
  explicit EpsilonConstraint(EpsilonPolicy policy);  // throws on an empty policy
  ScalarizationKind kind() const override { return ScalarizationKind::kEpsilonConstraint; }
  std::string describe() const override;
  Subproblem make_subproblem(const Linearization& lin) const override;
  std::unique_ptr<Scalarization> clone() const override;

  bool has_policy() const { return static_cast<bool>(policy_); }
  double fixed_epsilon() const { return epsilon_; }  // meaningful when !has_policy()
  double epsilon_for(const Linearization& lin) const;

 private:
  double epsilon_ = 0.0;
  EpsilonPolicy policy_;
};

// Checks what every backend relies on: b_j of size n, H_j n x n, a_j and all entries finite,
// n == expected_dim when expected_dim >= 0. Throws bivo::Error naming the offending part.
void validate_linearization(const Linearization& lin, int expected_dim = -1);

}  // namespace bivo::solvers
