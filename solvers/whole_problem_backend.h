#pragma once
// A backend that takes the whole nonlinear problem instead of one linearization (Ceres for
// the weighted sum, Ipopt over the manifold for the epsilon-constraint). It fills the same
// Summary as the outer loop so callers do not care which kind ran.
#include <string>

#include <Eigen/Core>

#include "solvers/problem.h"
#include "solvers/scalarization.h"
#include "solvers/summary.h"

namespace bivo::solvers {

class WholeProblemBackend {
 public:
  virtual ~WholeProblemBackend() = default;
  virtual std::string name() const = 0;
  virtual bool supports(ScalarizationKind kind) const = 0;
  // x: start on entry, solution on exit (ambient form of problem.manifold()). Never leaves
  // NaN in x: on failure x is the last good iterate and Summary::termination says why.
  virtual Summary solve(BiObjectiveProblem& problem, const Scalarization& scalarization, Eigen::VectorXd& x,
                        const SolverOptions& options) = 0;
};

}  // namespace bivo::solvers
