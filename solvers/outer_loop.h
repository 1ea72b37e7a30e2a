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
#include <string>

#include <Eigen/Core>

#include "solvers/problem.h"
#include "solvers/scalarization.h"
#include "solvers/step_backend.h"
#include "solvers/summary.h"

namespace bivo::solvers {

// By backend name (solvers/backend_registry.h): step or whole-problem backend.
Summary solve(BiObjectiveProblem& problem, const Scalarization& scalarization,
              const std::string& backend, Eigen::VectorXd& x, const SolverOptions& options = {});

// With a backend instance the caller keeps (e.g. reused across pyramid levels / frames).
// backend.reset() is called at the start.
Summary solve(BiObjectiveProblem& problem, const Scalarization& scalarization,
              StepBackend& backend, Eigen::VectorXd& x, const SolverOptions& options = {});

}  // namespace bivo::solvers
