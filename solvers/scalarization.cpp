#include "solvers/scalarization.h"

#include <cmath>
#include <sstream>

#include "solvers/error.h"

namespace bivo::solvers {
namespace {

double checked_parameter(const char* what, double value, const char* source) {
  if (!std::isfinite(value) || value < 0.0) {
    std::ostringstream msg;
    msg << what << " must be finite and >= 0, got " << value << " (" << source << ")";
    throw Error(msg.str());
  }
  return value;
}

void validate_model(const QuadraticModel& m, const char* which, Eigen::Index n) {
  std::ostringstream msg;
  if (m.b.size() != n || m.H.rows() != n || m.H.cols() != n) {
    msg << "linearization: model " << which << " has b of size " << m.b.size() << " and H of size " << m.H.rows() << "x"
        << m.H.cols() << ", expected " << n << " and " << n << "x" << n;
    throw Error(msg.str());
  }
  if (!std::isfinite(m.a) || !m.b.allFinite() || !m.H.allFinite()) {
    msg << "linearization: model " << which << " has non-finite entries (a = " << m.a << ", |b| = " << m.b.norm()
        << ", |H| = " << m.H.norm() << ")";
    throw Error(msg.str());
  }
}

}  // namespace

void validate_linearization(const Linearization& lin, int expected_dim) {
  const Eigen::Index n = expected_dim >= 0 ? expected_dim : lin.f1.b.size();
  if (n == 0) throw Error("linearization: empty model (no variables)");
  validate_model(lin.f1, "F_1", n);
  validate_model(lin.f2, "F_2", n);
}

WeightedSum::WeightedSum(double lambda) : lambda_(checked_parameter("lambda", lambda, "fixed weighted sum")) {}

WeightedSum::WeightedSum(LambdaPolicy policy) : policy_(std::move(policy)) {
  if (!policy_) throw Error("weighted sum: empty lambda policy");
}

std::string WeightedSum::describe() const {
  if (policy_) return "weighted sum (lambda from policy)";
  std::ostringstream s;
  s << "weighted sum (lambda = " << lambda_ << ")";
  return s.str();
}

double WeightedSum::lambda_for(const Linearization& lin) const {
  return policy_ ? checked_parameter("lambda", policy_(lin), "returned by the lambda policy") : lambda_;
}

Subproblem WeightedSum::make_subproblem(const Linearization& lin) const {
  validate_linearization(lin);
  Subproblem sp;
  sp.kind = ScalarizationKind::kWeightedSum;
  sp.lin = &lin;
  sp.lambda = lambda_for(lin);
  return sp;
}

std::unique_ptr<Scalarization> WeightedSum::clone() const { return std::make_unique<WeightedSum>(*this); }

EpsilonConstraint::EpsilonConstraint(double epsilon)
    : epsilon_(checked_parameter("epsilon", epsilon, "fixed epsilon-constraint")) {}

EpsilonConstraint::EpsilonConstraint(EpsilonPolicy policy) : policy_(std::move(policy)) {
  if (!policy_) throw Error("epsilon-constraint: empty epsilon policy");
}

std::string EpsilonConstraint::describe() const {
  if (policy_) return "epsilon-constraint (epsilon from policy)";
  std::ostringstream s;
  s << "epsilon-constraint (epsilon = " << epsilon_ << ")";
  return s.str();
}

double EpsilonConstraint::epsilon_for(const Linearization& lin) const {
  return policy_ ? checked_parameter("epsilon", policy_(lin), "returned by the epsilon policy") : epsilon_;
}

Subproblem EpsilonConstraint::make_subproblem(const Linearization& lin) const {
  validate_linearization(lin);
  Subproblem sp;
  sp.kind = ScalarizationKind::kEpsilonConstraint;
  sp.lin = &lin;
  sp.epsilon = epsilon_for(lin);
  return sp;
}

std::unique_ptr<Scalarization> EpsilonConstraint::clone() const { return std::make_unique<EpsilonConstraint>(*this); }

}  // namespace bivo::solvers
