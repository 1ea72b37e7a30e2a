#pragma once
// Helpers shared by the test files.
#include <algorithm>
#include <string>

#include <Eigen/Core>

#include "solvers/error.h"
#include "solvers/step_backend.h"

namespace bivo::testing {

// The message of the bivo::Error that f() throws, or "" when it throws none (other
// exceptions propagate and fail the test).
template <typename F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// |got - want| / max(1, |want|): relative error that stays absolute near zero.
inline double rel_err(const Eigen::VectorXd& got, const Eigen::VectorXd& want) {
  return (got - want).norm() / std::max(1.0, want.norm());
}

// The epsilon-constraint step subproblem of a linearization.
inline solvers::Subproblem eps_subproblem(const solvers::Linearization& lin, double epsilon) {
  solvers::Subproblem sp;
  sp.kind = solvers::ScalarizationKind::kEpsilonConstraint;
  sp.lin = &lin;
  sp.epsilon = epsilon;
  return sp;
}

}  // namespace bivo::testing
