#pragma once
// The entry point of the bi-objective layer.
//
//   solvers::WeightedSum ws(0.5);                       // or EpsilonConstraint eps(F2_bound)
//   solvers::SolverOptions opt;  opt.max_iterations = 20;
//   Eigen::VectorXd x = x0;                             // ambient form (7-vector for SE(3))
//   solvers::Summary s = solvers::solve(problem, ws, "gn", x, opt);
//   std::cout << s.FullReport();
//
// With a step backend the loop is: linearize -> scalarize -> step -> retract, stopping on
// step norm, relative decrease of the merit or the iteration budget (see SolverOptions).
// A NaN/Inf step or objective stops with TerminationReason::kNumericalFailure and x at the
// last good value. Whole-problem backends (ceres, ipopt-nlp) are dispatched by name too.
// A tracker calls solve() once per pyramid level with its own problem for that level.
//
// Errors (bivo::Error): unknown backend (message lists valid ones), backend that does not
// support the scalarization, x of the wrong size, non-finite objective or model at the start.
#include <optional>
#include <string>

#include <Eigen/Core>

#include "solvers/problem.h"
#include "solvers/scalarization.h"
#include "solvers/step_backend.h"
#include "solvers/summary.h"

namespace bivo::solvers {

// The latest linearization of a problem and the point it was made at, carried from one
// solve to the next on the SAME problem with nothing else linearizing it in between (a
// Pareto sweep). Out: every step-backend solve given a carry leaves its last linearization
// here (none after a whole-problem backend). In: a solve whose x equals carry->x exactly
// takes its first step from carry->lin instead of linearizing x again. The problem's
// weights are still those of that linearization, which evaluate() uses, so the solve is the
// one it would have been; a point of a sweep that needs one step then costs one evaluation
// instead of a linearization and an evaluation.
struct LinearizationCarry {
  Eigen::VectorXd x;
  std::optional<Linearization> lin;
};

// By backend name (solvers/backend_registry.h): step or whole-problem backend.
Summary solve(BiObjectiveProblem& problem, const Scalarization& scalarization, const std::string& backend,
              Eigen::VectorXd& x, const SolverOptions& options = {}, LinearizationCarry* carry = nullptr);

// With a backend instance the caller keeps (e.g. reused across pyramid levels / frames).
// backend.reset() is called at the start.
Summary solve(BiObjectiveProblem& problem, const Scalarization& scalarization, StepBackend& backend, Eigen::VectorXd& x,
              const SolverOptions& options = {}, LinearizationCarry* carry = nullptr);

}  // namespace bivo::solvers
