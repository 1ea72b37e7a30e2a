#pragma once
// What one solve is told (SolverOptions) and what it reports (Summary), shared by the outer
// loop (step backends) and the whole-problem backends (Ceres, Ipopt-NLP).
#include <functional>
#include <string>
#include <vector>

#include "solvers/profiling.h"
#include "solvers/step_backend.h"

namespace bivo::solvers {

struct SolverOptions {
  int max_iterations = 50;
  // Stop when the tangent step's Euclidean norm falls below this.
  double step_tolerance = 1e-10;
  // Stop when |merit_before - merit_after| <= tol * |merit_before|. The merit is
  // F_1 + lambda F_2 (weighted sum) or the Lagrangian F_1 + mu F_2 (epsilon-constraint,
  // mu of that step; F_2 alone while the step is infeasible).
  double relative_decrease_tolerance = 1e-12;
  int verbosity = 0;  // 0 silent, 1 one line per iteration on stderr
  // Phase times ("subproblem", "other", plus what the problem records in linearize:
  // "residuals", "weights", "normal_equations") are ALSO added here when not null; the
  // Summary always carries its own copy.
  PhaseProfile* profile = nullptr;
  // Ask the problem for full residual data even if the backend does not need it.
  bool want_full_residuals = false;
  // Optional size of a step in the problem's own units (odometry: the RMS image motion in
  // pixels it causes). When set and below step_measure_tolerance, the step is not taken
  // and the solve stops with kStepTolerance: a change nobody can see is not worth an
  // evaluation. Step backends only.
  std::function<double(const Eigen::VectorXd& x, const Eigen::VectorXd& delta)> step_measure;
  double step_measure_tolerance = 0.0;
  // The caller evaluates or linearizes the problem at the final x next (e.g. a second solve
  // from it): the last step is evaluated with evaluate(), which keeps the problem's data at
  // that x for reuse, rather than with evaluate_only().
  bool keep_final_point = false;
  // Extrapolated steps, for iterations that crawl (robust weights re-estimated at every
  // linearization make Gauss-Newton converge linearly: successive steps shrink by a nearly
  // constant ratio rho in a nearly constant direction). When a step points within cos > 0.7
  // of the previous one and rho, corrected for the previous step's own scale, lies in
  // (0.2, 0.95), the step is scaled by min(max_step_extrapolation, 1 / (1 - rho)): the sum
  // of the geometric tail (Aitken's extrapolation along the step). The scaled step is kept
  // only when its merit is below the merit before it; otherwise the plain step is evaluated
  // and taken (one more evaluation). The merit is that of the latest weights, whose quadratic
  // model the plain step minimizes: with residuals linear in the step a factor s changes it by
  // -s (2 - s) times the plain decrease, so factors of 2 or more are refused there. 1 = off
  // (the default). Step backends without an acceptance test of their own (not LM).
  double max_step_extrapolation = 1.0;
};

enum class TerminationReason {
  kStepTolerance,     // ||delta|| < step_tolerance, or step_measure below its tolerance
  kRelativeDecrease,  // merit changed by less than relative_decrease_tolerance
  kMaxIterations,     // budget exhausted
  kNoProgress,        // damped backend rejected too many steps in a row
  kNumericalFailure,  // NaN/Inf step or objective; x left at the last good value
  kBackendFailure,    // whole-problem backend (Ceres, Ipopt) reported failure
  kDegeneratePoint,   // the solve ended where the problem's objectives measure nothing
                      // (BiObjectiveProblem::degenerate); x reset to the start
};
const char* to_string(TerminationReason reason);

struct IterationRecord {
  int iteration = 0;          // 1-based
  double f1 = 0.0, f2 = 0.0;  // objectives AFTER this iteration (at the accepted x)
  double multiplier = 0.0;    // lambda (weighted sum) or mu (epsilon-constraint)
  double epsilon = 0.0;       // epsilon of this step (epsilon-constraint only)
  double step_norm = 0.0;     // of the backend's step, before any extrapolation
  double step_scale = 1.0;    // the factor the step was taken with (> 1: extrapolated)
  bool accepted = true;       // false: damped backend rejected the step, x unchanged
  bool feasible = true;       // the step backend's feasibility flag
  int inner_iterations = 0;   // the backend's own iterations for this step
  double seconds = 0.0;       // wall time of the whole iteration
  Eigen::VectorXd x;          // the iterate after this iteration (ambient form; unchanged
                              // when the step was rejected): the Python summary's `iterates`
};

struct Summary {
  std::string problem;
  std::string backend;
  ScalarizationKind kind = ScalarizationKind::kWeightedSum;
  std::string scalarization;  // Scalarization::describe()

  int iterations = 0;  // outer iterations run (accepted or not)
  // SolverOptions::max_step_extrapolation: steps taken extrapolated, and extrapolations
  // refused by the merit (each cost one evaluation more).
  int extrapolated_steps = 0;
  int refused_extrapolations = 0;
  double initial_f1 = 0.0, initial_f2 = 0.0;
  double final_f1 = 0.0, final_f2 = 0.0;
  double multiplier = 0.0;  // last lambda or mu (+inf when the last step was infeasible)
  double epsilon = 0.0;     // last epsilon (epsilon-constraint)
  bool feasible = true;     // last step feasible and, for epsilon, F_2 <= epsilon (1 + 1e-6): the
                            // slack of a converged nonlinear solve at the default tolerances

  TerminationReason termination = TerminationReason::kMaxIterations;
  std::string message;  // human-readable termination detail

  PhaseProfile phases;  // time per phase of this solve
  double total_seconds = 0.0;
  std::vector<IterationRecord> records;

  // Converged: stopped on a tolerance (not budget, not failure).
  bool converged() const {
    return termination == TerminationReason::kStepTolerance || termination == TerminationReason::kRelativeDecrease;
  }
  std::string BriefReport() const;  // one line
  std::string FullReport() const;   // multi-line, per-iteration table and phase times
};

}  // namespace bivo::solvers
