#include "odometry/tracker.h"

#include <sched.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <sstream>
#include <thread>
#include <utility>

#include "odometry/image_statistics.h"
#include "odometry/io/frame_stream.h"
#include "odometry/noise_bounded_level.h"
#include "odometry/robust_level.h"
#include "odometry/rolling_shutter.h"
#include "solvers/backend_registry.h"
#include "solvers/error.h"
#include "solvers/geometry/se3.h"
#include "solvers/outer_loop.h"
#include "solvers/scalarization.h"

namespace bivo::odometry {
namespace {

namespace se3 = solvers::se3;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

bool finite_pose(const Eigen::Isometry3d& T) { return T.matrix().allFinite(); }

// A solve that ended where the level's data gave no estimate: a degenerate point (x reset to
// its start) or a whole-problem backend that says it failed.
bool failed_solve(const solvers::Summary& s) {
  return s.termination == solvers::TerminationReason::kDegeneratePoint ||
         s.termination == solvers::TerminationReason::kBackendFailure;
}

constexpr double kNotEvaluated = std::numeric_limits<double>::quiet_NaN();

// Both starts: two estimates of a level closer than 0.5 deg and 1 cm are one minimum reached
// from two starts, and the photometric start's is kept (choosing between them by det S would
// only add noise); the basin failures both starts are for are errors of degrees. Above the
// largest such difference measured outside the held-out sequences (0.26 deg, 5 mm: the demo's
// renderings, real fr1/desk and fr3/long_office_household).
bool same_minimum(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  const Eigen::Isometry3d A = se3::from_ambient(a), B = se3::from_ambient(b);
  return se3::rotation_angle(A.inverse() * B) < 0.5 * M_PI / 180.0 && (A.translation() - B.translation()).norm() < 0.01;
}

// The reference frame's statistics as the method's rule reads them: the exact medians
// (tykkala only; ~1.5 ms per 640x480 frame) are computed here, once per reference frame,
// instead of in every frame's prepare_frame(); so are pi and the variances when the frame
// was prepared without them and the rule reads them.
FrameStatistics policy_statistics(Method method, const PreparedFrame& frame, int threads) {
  FrameStatistics s = frame.has_statistics || !reads_frame_statistics(method)
                          ? frame.statistics
                          : frame_statistics(frame.pyramid.levels[0], threads);
  if (reads_medians(method)) add_medians(s, frame.pyramid.levels[0]);
  return s;
}

}  // namespace

RgbdProblemOptions method_problem_options(Method method, const TrackerOptions& options) {
  RgbdProblemOptions o = options.problem;
  o.depth_first = method == Method::kDepth;
  o.joint_weights = uses_joint_weights(method);
  o.depth_noise_exponent = method_depth_noise_exponent(method, o.depth_noise_exponent);
  o.affine_brightness = method_affine_brightness(method, o.affine_brightness, options.vignetting > 0.0);
  o.min_valid_terms = std::max(o.min_valid_terms, options.min_valid_pixels);
  return o;
}

double process_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

double thread_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

namespace {

// The processors this process may run on (its affinity mask: taskset, Slurm's task binding),
// else the machine's; 0 when unknown.
unsigned usable_cores() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) == 0) return static_cast<unsigned>(CPU_COUNT(&set));
  return std::thread::hardware_concurrency();
}

}  // namespace

int load_threads_for(const TrackerOptions& options, unsigned cores) {
  if (!options.prefetch_frames) return 0;
  if (options.load_threads > 0) return options.load_threads;
  if (cores == 0) cores = usable_cores();
  return static_cast<long>(cores) >= static_cast<long>(options.problem.threads) + 2 ? 2 : 1;
}

PreparedFrame prepare_frame(io::RgbdImage image, const io::Intrinsics& K, int levels, int threads, int finest_level,
                            bool with_statistics) {
  PreparedFrame f;
  f.pyramid = build_pyramid(std::move(image), K, levels, threads, finest_level);
  if (with_statistics) {
    f.statistics = frame_statistics(f.pyramid.levels[0], threads);
    f.has_statistics = true;
  }
  return f;
}

namespace {

// One coarse-to-fine estimate on the frames as given.
PairResult estimate_once(const PreparedFrame& reference, const PreparedFrame& current, const Eigen::Isometry3d& initial,
                         const TrackerOptions& options) {
  const auto t0 = Clock::now();
  const double cpu0 = process_cpu_seconds();
  const Method method = parse_method(options.method);
  const std::string backend_name = tracker_backend(options);
  const bool whole_problem = solvers::is_whole_problem_backend(backend_name);
  std::unique_ptr<solvers::StepBackend> step_backend;
  if (!whole_problem) step_backend = solvers::make_step_backend(backend_name);
  const int levels = std::min<int>(options.levels, static_cast<int>(reference.pyramid.levels.size()));
  if (levels != options.levels || current.pyramid.levels.size() != reference.pyramid.levels.size()) {
    throw Error("estimate_motion: pyramids have " + std::to_string(reference.pyramid.levels.size()) + " and " +
                std::to_string(current.pyramid.levels.size()) + " levels, options ask for " +
                std::to_string(options.levels));
  }

  PairResult result;
  result.t_reference = reference.pyramid.timestamp;
  result.t_current = current.pyramid.timestamp;
  double lambda = 0.0, eps_bar = 0.0;
  if (method == Method::kBounded) {
    eps_bar = bounded_epsilon_per_weight(policy_statistics(method, reference, options.problem.threads), options.policy);
    result.epsilon_per_weight = eps_bar;
  } else if (!is_bounded(method) && !lambda_from_residuals(method) && method != Method::kRobust) {
    std::string why;
    const std::optional<double> defined =
        frame_lambda(method, policy_statistics(method, reference, options.problem.threads), options.policy, &why);
    if (!defined) {
      // The reference frame cannot weigh the objectives (no valid depth, no texture): an
      // invalid pair with the motion prior, as when every level is skipped (tracker.h).
      result.valid = false;
      result.T_21 = initial;
      result.note = "lambda undefined, " + why + ": motion prior used";
      result.seconds = seconds_since(t0);
      return result;
    }
    lambda = *defined;
    result.lambda = lambda;
  }
  RgbdProblemOptions problem_options = method_problem_options(method, options);
  const JacobianKind requested_jacobian = options.problem.jacobian;
  problem_options.jacobian = method_jacobian(method, requested_jacobian);
  // single and depth minimize F_1 alone: the other objective is not built per iteration.
  const bool one_objective = method == Method::kSingle || method == Method::kDepth;
  problem_options.model_f2 = !one_objective;

  solvers::SolverOptions solver_options;
  solver_options.max_iterations = options.max_iterations;
  solver_options.step_tolerance = options.step_tolerance;
  const double level_tolerance = uses_joint_weights(method)
                                     ? method_joint_tolerance(method, options.policy.joint_tolerance)
                                     : options.relative_decrease_tolerance;
  // method robust: once a level's depth failed the trust test, the finer levels are
  // photometric (a biased sensor is biased at every resolution).
  bool depth_distrusted = false;
  solver_options.max_step_extrapolation = method_step_extrapolation(method, options.step_extrapolation);
  solver_options.profile = &result.profile;
  solver_options.verbosity = options.verbosity;
  // noise-bounded evaluates F_I at each stage's final x after its solve.
  solver_options.keep_final_point = method == Method::kNoiseBounded;

  const int photometric_start_levels = method_photometric_start_levels(method, options.policy.photometric_start_levels);
  const bool both_starts = options.policy.both_starts == 1;
  Eigen::VectorXd x = se3::to_ambient(initial);
  bool any_level_solved = false;
  for (int level = levels - 1; level >= options.finest_level; --level) {
    LevelResult lr;
    lr.level = level;
    const auto t_reference = Clock::now();
    const bool finest = level == options.finest_level;
    solver_options.relative_decrease_tolerance =
        method == Method::kRobust && finest ? options.policy.robust_finest_tolerance : level_tolerance;
    solver_options.step_tolerance =
        method == Method::kRobust && finest && options.policy.robust_finest_step_tolerance >= 0.0
            ? options.policy.robust_finest_step_tolerance
            : options.step_tolerance;
    RgbdProblemOptions level_options = problem_options;
    level_options.jacobian = method_jacobian(method, requested_jacobian, finest);
    if (depth_distrusted) {  // robust: single's problem
      level_options.joint_weights = false;
      level_options.model_f2 = false;
      level_options.jacobian = JacobianKind::kForward;
    }
    RgbdOdometryProblem problem(reference.pyramid.levels[level], current.pyramid.levels[level], level_options);
    result.profile.add("reference", seconds_since(t_reference));
    lr.terms = problem.num_terms();
    if (lr.terms < options.min_valid_pixels) {
      lr.skipped = true;
      lr.termination = "skipped: " + std::to_string(lr.terms) + " reference pixels with valid depth";
      result.note += "level " + std::to_string(level) + " " + lr.termination + "; ";
      result.levels.push_back(lr);
      continue;
    }
    // F_I holds no information where an image has no contrast (black, saturated): every method
    // that reads F_I would report a pose it moved for nothing.
    if (method != Method::kDepth && (!has_contrast(reference.pyramid.levels[level].intensity) ||
                                     !has_contrast(current.pyramid.levels[level].intensity))) {
      lr.skipped = true;
      lr.termination = "skipped: an image without contrast (every intensity within 1 gray level)";
      result.note += "level " + std::to_string(level) + " " + lr.termination + "; ";
      result.levels.push_back(lr);
      continue;
    }
    const Eigen::VectorXd x_before = x;
    double level_lambda = lambda;
    // The level's solve on `on` (the method's scalarization from x); fills the method-specific
    // parts of lr. Run once, and again for the exact finish.
    const auto solve_level = [&](RgbdOdometryProblem& on) {
      if (options.pixel_motion_tolerance > 0.0) {
        solver_options.step_measure = [&on](const Eigen::VectorXd& at, const Eigen::VectorXd& delta) {
          return on.pixel_motion(at, delta);
        };
        solver_options.step_measure_tolerance = options.pixel_motion_tolerance;
      }
      const auto run_with = [&](const solvers::Scalarization& scalarization, const solvers::SolverOptions& so) {
        return whole_problem ? solvers::solve(on, scalarization, backend_name, x, so)
                             : solvers::solve(on, scalarization, *step_backend, x, so);
      };
      const auto run = [&](const solvers::Scalarization& scalarization) {
        return run_with(scalarization, solver_options);
      };
      RgbdOdometryProblem* p = &on;
      if (method == Method::kRobust) {
        if (depth_distrusted) {
          lr.relaxed = true;
          return run(solvers::WeightedSum(0.0));
        }
        const RobustLevel rl = solve_robust_level(on, options.policy, run_with, solver_options,
                                                  finest ? options.exact_finish_iterations : 0, x);
        lr.relaxed = depth_distrusted = rl.distrusted;
        lr.trust = rl.statistic;
        level_lambda = rl.lambda;
        return rl.summary;
      }
      if (method == Method::kBounded) {
        // eps_D = eps_bar * trace(Omega_D) of this linearization (odometry_methods.h).
        return run(solvers::EpsilonConstraint(
            [p, eps_bar](const solvers::Linearization&) { return eps_bar * p->last_stats().weight_sum_depth; }));
      }
      if (method == Method::kNoiseBounded) {
        const NoiseBoundedLevel nb = solve_noise_bounded(on, options.policy, run, solver_options, x);
        lr.relaxed = nb.relaxed;
        lr.guard_rise = nb.rise;
        result.epsilon_per_weight = nb.eps_bar;
        return nb.summary;
      }
      if (lambda_from_residuals(method)) {
        const PolicyParameters policy = options.policy;
        double* last = &level_lambda;
        return run(solvers::WeightedSum([p, method, policy, last](const solvers::Linearization&) {
          return *last = residual_lambda(method, p->last_stats(), policy);
        }));
      }
      return run(solvers::WeightedSum(lambda));
    };
    int start_iterations = 0;
    const bool photometric_start =
        uses_joint_weights(method) && !depth_distrusted && level >= levels - photometric_start_levels;
    // PolicyParameters::both_starts: the level solved from the prior first, on a problem of
    // its own (the photometric start below runs exactly as without it), kept aside.
    struct Candidate {
      Eigen::VectorXd x;
      solvers::Summary summary;
      LevelResult lr;
      bool distrusted = false;
      double lambda = 0.0, determinant = 0.0;
    };
    std::optional<RgbdOdometryProblem> prior_problem;
    std::optional<Candidate> from_prior;
    if (photometric_start && both_starts) {
      const LevelResult lr_before = lr;
      const auto t_prior = Clock::now();
      prior_problem.emplace(reference.pyramid.levels[level], current.pyramid.levels[level], level_options);
      result.profile.add("reference", seconds_since(t_prior));
      from_prior = Candidate{};
      from_prior->summary = solve_level(*prior_problem);
      from_prior->x = x;
      from_prior->lr = lr;
      from_prior->distrusted = depth_distrusted;
      from_prior->lambda = level_lambda;
      from_prior->determinant = prior_problem->last_stats().joint_scale.determinant();
      x = x_before;
      lr = lr_before;
      depth_distrusted = false;
      level_lambda = lambda;
    }
    if (photometric_start) {
      // The photometric objective's basin is the wider one for large rotations (the depth
      // objective's landscape folds where points change surface): F_I alone first, with its
      // own weights, then the bi-objective solve from there.
      problem.set_objectives(false, false);
      start_iterations =
          (whole_problem ? solvers::solve(problem, solvers::WeightedSum(0.0), backend_name, x, solver_options)
                         : solvers::solve(problem, solvers::WeightedSum(0.0), *step_backend, x, solver_options))
              .iterations;
      problem.set_objectives(true, true);
    }
    solvers::Summary summary = solve_level(problem);
    summary.iterations += start_iterations;
    RgbdOdometryProblem* solved = &problem;  // the problem whose estimate the level keeps
    if (from_prior) {
      // Where the two starts found different minima, the smaller generalized variance wins; a
      // tie keeps the photometric start. A start whose solve ended degenerate (x reset, S of the
      // degenerate point) or failed cannot win.
      const auto usable = [](const solvers::Summary& s, const Eigen::VectorXd& at) {
        return at.allFinite() && !failed_solve(s);
      };
      const double det = problem.last_stats().joint_scale.determinant();
      const int iterations = summary.iterations + from_prior->summary.iterations;
      const bool prior_wins =
          usable(from_prior->summary, from_prior->x) && from_prior->determinant > 0.0 &&
          (!usable(summary, x) || !(det > 0.0) || (from_prior->determinant < det && !same_minimum(from_prior->x, x)));
      if (prior_wins) {
        x = from_prior->x;
        summary = from_prior->summary;
        lr = from_prior->lr;
        lr.kept_prior = true;
        depth_distrusted = from_prior->distrusted;
        level_lambda = from_prior->lambda;
        solved = &*prior_problem;
      }
      summary.iterations = iterations;
    }
    // Reference-side (inverse / ESM) gradients make the Jacobian an approximation whose fixed
    // point is not the cost's stationary point; the exact finish continues the finest level
    // from there with current-side gradients (TrackerOptions::exact_finish_iterations).
    if (method != Method::kRobust && options.exact_finish_iterations > 0 && finest &&
        level_options.jacobian != JacobianKind::kForward && x.allFinite()) {
      const int first_iterations = summary.iterations;
      solved->set_jacobian(JacobianKind::kForward);  // weights and scales carried over
      const int level_iterations = solver_options.max_iterations;
      solver_options.max_iterations = std::min(level_iterations, options.exact_finish_iterations);
      summary = solve_level(*solved);
      solver_options.max_iterations = level_iterations;
      summary.iterations += first_iterations;
    }
    if (lr.relaxed) {
      ++result.relaxed_levels;
      result.note += "level " + std::to_string(level) + " bound relaxed; ";
    }
    const RgbdLinearizationStats& stats = solved->last_stats();
    lr.valid_intensity = stats.valid_intensity;
    lr.valid_depth = stats.valid_depth;
    lr.iterations = summary.iterations;
    lr.termination = solvers::to_string(summary.termination);
    result.iterations += summary.iterations;
    // A degenerate end, or a whole-problem backend that says it failed: no estimate here.
    const bool degenerate = failed_solve(summary);
    if (!x.allFinite() || degenerate || stats.valid_intensity < options.min_valid_pixels) {
      x = x_before;  // the level's data could not support an estimate: keep the coarser one
      lr.skipped = true;
      lr.termination = degenerate ? "skipped: " + summary.message
                                  : "skipped: " + std::to_string(stats.valid_intensity) + " valid pixels after warping";
      result.note += "level " + std::to_string(level) + " " + lr.termination + "; ";
      result.levels.push_back(lr);
      continue;
    }
    any_level_solved = true;
    lr.f_i = problem_options.depth_first ? summary.final_f2 : summary.final_f1;
    lr.f_d = problem_options.depth_first ? summary.final_f1 : summary.final_f2;
    if (one_objective) {
      if (options.evaluate_unused_objective) {
        const std::array<double, 2> f = solved->objectives_at(x, &result.profile);
        (problem_options.depth_first ? lr.f_i : lr.f_d) = f[problem_options.depth_first ? 0 : 1];
      } else {
        (problem_options.depth_first ? lr.f_i : lr.f_d) = kNotEvaluated;
      }
    }
    if (is_bounded(method)) {
      lr.epsilon = summary.epsilon;
      lr.mu = summary.multiplier;
    } else {
      lr.lambda = level_lambda;
      lr.correlation = stats.joint_scale.correlation();
      result.lambda = lr.lambda;
      result.correlation = lr.correlation;
      result.trust = lr.trust;
    }
    result.f_i = lr.f_i;
    result.f_d = lr.f_d;
    result.epsilon = lr.epsilon;
    result.mu = lr.mu;
    result.levels.push_back(lr);
  }
  result.T_21 = se3::from_ambient(x);
  if (!any_level_solved || !finite_pose(result.T_21)) {
    result.valid = false;
    result.T_21 = initial;
    result.note += "no level could be solved: motion prior used";
  }
  result.seconds = seconds_since(t0);
  result.cpu_seconds = process_cpu_seconds() - cpu0;
  return result;
}

}  // namespace

PairResult estimate_motion(const PreparedFrame& reference, const PreparedFrame& current,
                           const Eigen::Isometry3d& initial, const TrackerOptions& options) {
  const double interval = current.pyramid.timestamp - reference.pyramid.timestamp;
  // A rolling shutter retimes unsynchronized depth too (TrackerOptions::readout_time).
  const bool unroll = options.readout_time > 0.0;
  const bool retime = (options.retime_depth == 1 || unroll) &&
                      (reference.pyramid.depth_delay != 0.0 || current.pyramid.depth_delay != 0.0);
  if (!(interval > 0.0) || (!retime && !unroll)) return estimate_once(reference, current, initial, options);
  // Estimated on the frames as given, then on their images moved to their timestamps from the
  // latest estimate, TrackerOptions::correction_rounds times.
  PairResult latest = estimate_once(reference, current, initial, options);
  const double middle = reference.pyramid.timestamp + 0.5 * interval;
  const bool before = reference.arrival_velocity && reference.arrival_time < middle;
  const int rounds = method_correction_rounds(parse_method(options.method), options.correction_rounds);
  for (int round = 0; round < rounds && latest.valid; ++round) {
    const auto t0 = Clock::now();
    const double cpu0 = process_cpu_seconds();
    // The velocity at each frame's time: linear through the pair before (when known) and this one.
    const se3::Vector6d velocity = se3::log(latest.T_21) / interval;
    const se3::Vector6d acceleration =
        before ? se3::Vector6d((velocity - *reference.arrival_velocity) / (middle - reference.arrival_time))
               : se3::Vector6d::Zero();
    const auto corrected = [&](const PreparedFrame& f) {
      PreparedFrame r;
      const se3::Vector6d at_frame = velocity + (f.pyramid.timestamp - middle) * acceleration;
      r.pyramid = pyramid_at_timestamp(f.pyramid, at_frame, retime, options.readout_time, options.problem.threads);
      r.statistics = f.statistics;
      r.has_statistics = f.has_statistics;
      return r;
    };
    // The two frames are moved side by side (a worker takes one with threads >= 2).
    PreparedFrame reference_corrected, current_corrected;
    run_beside(
        options.problem.threads, [&] { current_corrected = corrected(current); },
        [&] { reference_corrected = corrected(reference); });
    const double correct_seconds = seconds_since(t0), correct_cpu = process_cpu_seconds() - cpu0;
    PairResult next = estimate_once(reference_corrected, current_corrected, latest.T_21, options);
    if (!next.valid) {  // the latest estimate stands, not the prior this round fell back to
      latest.note += std::string(latest.note.empty() ? "" : "; ") + "on corrected frames: " + next.note;
      latest.seconds += correct_seconds + next.seconds;
      latest.cpu_seconds += correct_cpu + next.cpu_seconds;
      latest.iterations += next.iterations;
      return latest;
    }
    next.iterations += latest.iterations;
    next.seconds += latest.seconds + correct_seconds;
    next.cpu_seconds += latest.cpu_seconds + correct_cpu;
    next.profile.merge(latest.profile);
    next.profile.add("correct_frames", correct_seconds);
    latest = std::move(next);
  }
  return latest;
}

std::unique_ptr<RgbdOdometryProblem> FramePair::problem(int level, const TrackerOptions& options) const {
  if (level < 0 || level >= static_cast<int>(reference.pyramid.levels.size())) {
    throw Error("frame pair: level " + std::to_string(level) + " outside 0.." +
                std::to_string(reference.pyramid.levels.size() - 1));
  }
  const Method method = parse_method(options.method);
  RgbdProblemOptions po = method_problem_options(method, as_loaded(options));
  po.jacobian = method_jacobian(method, options.problem.jacobian, level == options.finest_level);
  return std::make_unique<RgbdOdometryProblem>(reference.pyramid.levels[level], current.pyramid.levels[level], po);
}

double FramePair::lambda(const TrackerOptions& options) const {
  const Method method = parse_method(options.method);
  return method_lambda(method, policy_statistics(method, reference, options.problem.threads), options.policy);
}

double FramePair::epsilon_per_weight(const TrackerOptions& options) const {
  return bounded_epsilon_per_weight(policy_statistics(Method::kBounded, reference, options.problem.threads),
                                    options.policy);
}

}  // namespace bivo::odometry
