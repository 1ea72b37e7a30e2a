// linearize -> scalarize -> step -> retract, until a tolerance or the budget stops it.
#include "solvers/outer_loop.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <sstream>
#include <string>

#include "solvers/backend_registry.h"
#include "solvers/error.h"

namespace bivo::solvers {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

bool finite2(const std::array<double, 2>& f) { return std::isfinite(f[0]) && std::isfinite(f[1]); }

bool finite_models(const Linearization& lin) {
  return std::isfinite(lin.f1.a) && std::isfinite(lin.f2.a) && lin.f1.b.allFinite() && lin.f2.b.allFinite() &&
         lin.f1.H.allFinite() && lin.f2.H.allFinite();
}

// The merit the stopping rule and the acceptance test compare (see SolverOptions): the
// weighted sum itself, or the Lagrangian F_1 + mu F_2 of the epsilon-constraint step; an
// infeasible step (mu = inf) is judged by F_2 alone.
double merit(const std::array<double, 2>& f, const Subproblem& sp, const StepResult& step) {
  if (sp.kind == ScalarizationKind::kWeightedSum) return f[0] + sp.lambda * f[1];
  if (!std::isfinite(step.multiplier)) return f[1];
  return f[0] + step.multiplier * f[1];
}

// SolverOptions::max_step_extrapolation: the factor for `delta`, given the previous
// iteration's step `previous` (as the backend returned it) and the factor it was taken
// with. A plain step shrinking by rho per iteration leaves a tail of rho / (1 - rho) of
// itself: 1 / (1 - rho) covers it. After a step taken s times, the next plain step is
// (1 - s (1 - rho)) of it, from which rho is recovered.
double extrapolation_factor(const Eigen::VectorXd& delta, const Eigen::VectorXd& previous, double previous_scale,
                            double max_factor) {
  const double n = delta.norm(), n_previous = previous.norm();
  if (!(max_factor > 1.0) || !(n > 0.0) || !(n_previous > 0.0)) return 1.0;
  if (delta.dot(previous) < 0.7 * n * n_previous) return 1.0;  // turned: not a crawl
  const double rho = 1.0 - (1.0 - n / n_previous) / previous_scale;
  if (!(rho > 0.2 && rho < 0.95)) return 1.0;
  return std::min(max_factor, 1.0 / (1.0 - rho));
}

// A solve that ends where the problem's objectives measure nothing (degenerate()) has
// failed, whatever its tolerances said: x goes back to where the solve started.
void reject_degenerate_end(BiObjectiveProblem& problem, const Eigen::VectorXd& x_start, Eigen::VectorXd& x,
                           Summary& summary) {
  if (!x.allFinite()) return;
  const std::optional<std::string> why = problem.degenerate(x);
  if (!why) return;
  summary.termination = TerminationReason::kDegeneratePoint;
  summary.message = "degenerate point (" + *why + "); x reset to the start of the solve";
  x = x_start;
  summary.final_f1 = summary.initial_f1;
  summary.final_f2 = summary.initial_f2;
}

}  // namespace

Summary solve(BiObjectiveProblem& problem, const Scalarization& scalarization, StepBackend& backend, Eigen::VectorXd& x,
              const SolverOptions& options, LinearizationCarry* carry) {
  const auto t_start = Clock::now();
  const Manifold& manifold = problem.manifold();
  if (x.size() != manifold.ambient_dim()) {
    std::ostringstream msg;
    msg << "solve(" << problem.name() << "): x has " << x.size() << " entries, the manifold needs "
        << manifold.ambient_dim();
    throw Error(msg.str());
  }
  if (!x.allFinite()) throw Error("solve(" + problem.name() + "): the initial x has NaN/Inf entries");
  if (!backend.supports(scalarization.kind())) {
    throw Error("backend '" + backend.name() + "' does not support " + scalarization.describe());
  }
  if (options.max_iterations < 0) {
    throw Error("solve: max_iterations must be >= 0, got " + std::to_string(options.max_iterations));
  }

  const Eigen::VectorXd x_start = x;
  Summary summary;
  summary.problem = problem.name();
  summary.backend = backend.name();
  summary.kind = scalarization.kind();
  summary.scalarization = scalarization.describe();
  backend.reset();

  LinearizeOptions lin_options;
  lin_options.want_full = backend.needs_full_residuals() || options.want_full_residuals;
  lin_options.update_weights = true;
  lin_options.profile = &summary.phases;

  const bool carried = carry && carry->lin && carry->x.size() == x.size() && carry->x == x &&
                       (!lin_options.want_full || (carry->lin->full1 && carry->lin->full2));
  Linearization lin = carried ? std::move(*carry->lin) : problem.linearize(x, lin_options);
  if (carry) carry->lin.reset();  // refilled at the end, when the last linearization is known
  validate_linearization(lin, manifold.tangent_dim());
  // Carried: F_j(x) under the carried weights are the models' constants, as after a
  // linearization inside the loop below.
  std::array<double, 2> f = carried ? std::array<double, 2>{lin.f1.a, lin.f2.a} : problem.evaluate(x);
  Eigen::VectorXd x_lin = x;  // where `lin` was made
  bool lin_usable = true;     // false once a linearization had NaN/Inf entries
  if (!finite2(f)) {
    std::ostringstream msg;
    msg << "solve(" << problem.name() << "): objectives at the initial x are not finite (F1 = " << f[0]
        << ", F2 = " << f[1] << ")";
    throw Error(msg.str());
  }
  summary.initial_f1 = f[0];
  summary.initial_f2 = f[1];
  summary.termination = TerminationReason::kMaxIterations;
  summary.message = "reached max_iterations = " + std::to_string(options.max_iterations);

  Eigen::VectorXd previous_step;  // the last iteration's step (extrapolation; empty before)
  double previous_scale = 1.0;
  int consecutive_rejections = 0;
  const int max_rejections = 30;  // LM: damping grows 4x per rejection, 4^30 ~ 1e18
  bool last_feasible = true;
  bool stop = false;
  for (int it = 1; it <= options.max_iterations && !stop; ++it) {
    const auto t_iter = Clock::now();
    Subproblem sp = scalarization.make_subproblem(lin);
    sp.profile = &summary.phases;
    StepResult step;
    {
      ScopedPhase phase(&summary.phases, "subproblem");
      step = backend.solve(sp);
    }
    IterationRecord rec;
    rec.iteration = it;
    rec.multiplier = step.multiplier;
    rec.epsilon = sp.epsilon;
    rec.feasible = step.feasible;
    rec.inner_iterations = step.iterations;
    summary.iterations = it;
    summary.multiplier = step.multiplier;
    summary.epsilon = sp.epsilon;
    last_feasible = step.feasible;
    // Ends the solve at this iteration without taking its step: x and F stay.
    const auto stop_without_step = [&](TerminationReason reason, std::string message) {
      summary.termination = reason;
      summary.message = std::move(message);
      rec.accepted = false;
      rec.f1 = f[0];
      rec.f2 = f[1];
      rec.seconds = seconds_since(t_iter);
      rec.x = x;
      summary.records.push_back(rec);
    };

    if (step.delta.size() != manifold.tangent_dim()) {
      std::ostringstream msg;
      msg << "backend '" << backend.name() << "' returned a step of size " << step.delta.size() << ", expected "
          << manifold.tangent_dim();
      throw Error(msg.str());
    }
    if (!step.delta.allFinite()) {
      stop_without_step(TerminationReason::kNumericalFailure,
                        "backend '" + backend.name() + "' returned a NaN/Inf step (" + step.status + ")");
      break;
    }
    rec.step_norm = step.delta.norm();
    if (options.step_measure && options.step_measure_tolerance > 0.0) {
      const double size = options.step_measure(x, step.delta);
      if (size < options.step_measure_tolerance) {
        std::ostringstream msg;
        msg << "step measure " << size << " < " << options.step_measure_tolerance << " (step not taken)";
        stop_without_step(TerminationReason::kStepTolerance, msg.str());
        break;
      }
    }
    // The last step, whatever its value (the tests below stop on it): nothing will
    // linearize at x_new.
    const bool last = rec.step_norm < options.step_tolerance || it == options.max_iterations;
    const auto evaluate_at = [&](const Eigen::VectorXd& at) {
      if (!at.allFinite()) return std::array<double, 2>{NAN, NAN};
      ScopedPhase phase(&summary.phases, "residuals");  // evaluate() is a residual pass
      return last && !options.keep_final_point ? problem.evaluate_only(at) : problem.evaluate(at);
    };
    const double scale =
        last || backend.wants_acceptance_test() || previous_step.size() != step.delta.size()
            ? 1.0
            : extrapolation_factor(step.delta, previous_step, previous_scale, options.max_step_extrapolation);
    Eigen::VectorXd x_new = manifold.retract(x, scale * step.delta);
    std::array<double, 2> f_new = evaluate_at(x_new);
    rec.step_scale = scale;
    if (scale > 1.0) {
      if (finite2(f_new) && merit(f_new, sp, step) < merit(f, sp, step)) {
        ++summary.extrapolated_steps;
      } else {  // the plain step, evaluated again
        ++summary.refused_extrapolations;
        rec.step_scale = 1.0;
        x_new = manifold.retract(x, step.delta);
        f_new = evaluate_at(x_new);
      }
    }
    previous_step = step.delta;
    previous_scale = rec.step_scale;
    if (!finite2(f_new)) {
      stop_without_step(TerminationReason::kNumericalFailure,
                        "objective is NaN/Inf after the step; x kept at the last good value");
      break;
    }
    const double merit_old = merit(f, sp, step);
    const double merit_new = merit(f_new, sp, step);
    bool accepted = true;
    if (backend.wants_acceptance_test()) {
      accepted = merit_new <= merit_old;
      backend.on_step_evaluated(accepted);
    }
    if (accepted) {
      x = x_new;
      f = f_new;
      consecutive_rejections = 0;
    } else {
      ++consecutive_rejections;
    }
    rec.accepted = accepted;
    rec.f1 = f[0];
    rec.f2 = f[1];

    if (rec.step_norm < options.step_tolerance) {
      summary.termination = TerminationReason::kStepTolerance;
      summary.message = "|step| = " + std::to_string(rec.step_norm);
      stop = true;
    } else if (std::abs(merit_old - merit_new) <= options.relative_decrease_tolerance * std::abs(merit_old)) {
      summary.termination = TerminationReason::kRelativeDecrease;
      std::ostringstream msg;
      msg << "merit " << merit_old << " -> " << merit_new;
      summary.message = msg.str();
      stop = true;
    } else if (consecutive_rejections >= max_rejections) {
      summary.termination = TerminationReason::kNoProgress;
      summary.message = std::to_string(max_rejections) + " consecutive rejected steps";
      stop = true;
    }
    if (!stop && accepted && it < options.max_iterations) {
      lin = problem.linearize(x, lin_options);
      x_lin = x;
      if (!finite_models(lin)) {
        lin_usable = false;
        summary.termination = TerminationReason::kNumericalFailure;
        summary.message = "linearization at the accepted x has NaN/Inf entries";
        stop = true;
      } else {
        // The models' constants are F_j(x) under the re-estimated weights, so the next merit
        // comparison is made on the objective the next step approximates.
        f = {lin.f1.a, lin.f2.a};
      }
    }
    rec.seconds = seconds_since(t_iter);
    rec.x = x;
    summary.records.push_back(rec);
    if (options.verbosity > 0) {
      std::fprintf(stderr, "bivo %s it %3d F1 %.6e F2 %.6e mult %.4e |d| %.3e %s%s\n", backend.name().c_str(), it,
                   rec.f1, rec.f2, rec.multiplier, rec.step_norm, accepted ? "" : "rejected ",
                   step.feasible ? "" : "infeasible");
    }
  }

  if (carry && lin_usable) {
    carry->x = std::move(x_lin);
    carry->lin = std::move(lin);
  }
  summary.final_f1 = f[0];
  summary.final_f2 = f[1];
  summary.feasible = last_feasible;
  if (summary.kind == ScalarizationKind::kEpsilonConstraint && summary.iterations > 0) {
    summary.feasible = last_feasible && f[1] <= summary.epsilon * (1.0 + 1e-6) + 1e-300;
  }
  reject_degenerate_end(problem, x_start, x, summary);
  summary.total_seconds = seconds_since(t_start);
  const double accounted = summary.phases.total_seconds();
  summary.phases.add("other", std::max(0.0, summary.total_seconds - accounted));
  if (options.profile) options.profile->merge(summary.phases);
  return summary;
}

Summary solve(BiObjectiveProblem& problem, const Scalarization& scalarization, const std::string& backend,
              Eigen::VectorXd& x, const SolverOptions& options, LinearizationCarry* carry) {
  const BackendInfo& info = backend_info(backend);
  if (info.whole_problem) {
    if (carry) carry->lin.reset();  // it linearizes and evaluates the problem its own way
    auto whole = info.make_whole();
    if (!whole->supports(scalarization.kind())) {
      throw Error("backend '" + backend + "' does not support " + scalarization.describe());
    }
    const Eigen::VectorXd x_start = x;
    Summary summary = whole->solve(problem, scalarization, x, options);
    reject_degenerate_end(problem, x_start, x, summary);
    return summary;
  }
  auto step = info.make_step();
  return solve(problem, scalarization, *step, x, options, carry);
}

}  // namespace bivo::solvers
