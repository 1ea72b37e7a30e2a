// The tracker's options by name and their one check (tracker.h).
#include <cmath>
#include <string>

#include "odometry/io/frame_stream.h"
#include "odometry/odometry_methods.h"
#include "odometry/tracker.h"
#include "solvers/backend_registry.h"
#include "solvers/error.h"

namespace bivo::odometry {

std::string tracker_backend(const TrackerOptions& options) {
  return options.backend.empty() ? default_backend(parse_method(options.method)) : options.backend;
}

InitialGuess parse_initial_guess(const std::string& name) {
  if (name == "identity") return InitialGuess::kIdentity;
  if (name == "constant-velocity" || name == "cv") return InitialGuess::kConstantVelocity;
  throw Error("unknown initial guess '" + name + "' (valid: identity, constant-velocity)");
}

const char* to_string(InitialGuess guess) {
  return guess == InitialGuess::kIdentity ? "identity" : "constant-velocity";
}

void validate(const TrackerOptions& options) {
  const Method method = parse_method(options.method);
  const std::string backend = tracker_backend(options);
  const solvers::BackendInfo& info = solvers::backend_info(backend);  // throws listing valid names
  const bool ok = is_bounded(method) ? info.epsilon_constraint : info.weighted_sum;
  if (!ok) {
    std::string valid;
    for (const auto& b : solvers::backend_infos()) {
      if (is_bounded(method) ? b.epsilon_constraint : b.weighted_sum) valid += (valid.empty() ? "" : ", ") + b.name;
    }
    throw Error("backend '" + backend + "' cannot solve method '" + options.method + "' (" +
                (is_bounded(method) ? "epsilon-constraint" : "weighted sum") + "; valid: " + valid + ")");
  }
  if (options.levels < 1 || options.levels > 8) {
    throw Error("levels must be in 1..8, got " + std::to_string(options.levels));
  }
  if (options.finest_level < 0 || options.finest_level >= options.levels) {
    throw Error("finest level must be in 0.." + std::to_string(options.levels - 1) + ", got " +
                std::to_string(options.finest_level));
  }
  if (options.exact_finish_iterations < 0) {
    throw Error("exact finish iterations must be >= 0 (0: off), got " +
                std::to_string(options.exact_finish_iterations));
  }
  if (options.retry_from_rest != 0 && options.retry_from_rest != 1) {
    throw Error("retry from rest must be 0 or 1, got " + std::to_string(options.retry_from_rest));
  }
  if (options.retime_depth != 0 && options.retime_depth != 1) {
    throw Error("retime depth must be 0 or 1, got " + std::to_string(options.retime_depth));
  }
  if (!(options.readout_time == -1.0 || (options.readout_time >= 0.0 && options.readout_time <= 1.0))) {
    throw Error("readout time must be -1 (the sequence's) or in [0, 1] s, got " + std::to_string(options.readout_time));
  }
  if (!(options.vignetting == -1.0 || (options.vignetting >= 0.0 && options.vignetting < 1.0))) {
    throw Error("vignetting must be -1 (the sequence's) or a fall-off in [0, 1), got " +
                std::to_string(options.vignetting));
  }
  if (!(options.problem.min_valid_fraction >= 0.0 && options.problem.min_valid_fraction <= 1.0)) {
    throw Error("min valid fraction must be in [0, 1], got " + std::to_string(options.problem.min_valid_fraction));
  }
  if (options.max_iterations < 1) {
    throw Error("max iterations per level must be >= 1, got " + std::to_string(options.max_iterations));
  }
  if (options.policy.eps_min < 0 || options.policy.eps_max < 0 || !std::isfinite(options.policy.eps_max) ||
      (options.policy.eps && !(*options.policy.eps >= 0.0 && std::isfinite(*options.policy.eps)))) {
    throw Error("epsilon bounds must be finite and >= 0");
  }
  if (method == Method::kFixed && !(options.policy.lambda >= 0.0 && std::isfinite(options.policy.lambda))) {
    throw Error("fixed lambda must be finite and >= 0, got " + std::to_string(options.policy.lambda));
  }
  if (!(options.policy.kappa >= 0.0 && std::isfinite(options.policy.kappa))) {
    throw Error("kappa must be finite and >= 0, got " + std::to_string(options.policy.kappa));
  }
  if (!(options.policy.eps_ratio > 0.0 && std::isfinite(options.policy.eps_ratio))) {
    throw Error("eps ratio must be finite and > 0, got " + std::to_string(options.policy.eps_ratio));
  }
  const double jt = options.policy.joint_tolerance;
  if (!(jt == -1.0 || (jt >= 0.0 && std::isfinite(jt)))) {
    throw Error("joint tolerance must be finite and >= 0 (or -1, the method's own), got " + std::to_string(jt));
  }
  if (!(options.policy.relaxed_tolerance >= 0.0 && std::isfinite(options.policy.relaxed_tolerance))) {
    throw Error("relaxed tolerance must be finite and >= 0, got " + std::to_string(options.policy.relaxed_tolerance));
  }
  if (!(options.policy.trust >= 0.0 && std::isfinite(options.policy.trust))) {
    throw Error("trust threshold must be finite and >= 0, got " + std::to_string(options.policy.trust));
  }
  if (options.policy.photometric_start_levels < -1) {
    throw Error("photometric start levels must be >= 0, or -1 for the method's own, got " +
                std::to_string(options.policy.photometric_start_levels));
  }
  if (options.policy.both_starts != 0 && options.policy.both_starts != 1) {
    throw Error("both starts must be 0 or 1, got " + std::to_string(options.policy.both_starts));
  }
  if (!(options.policy.guard >= 0.0 && std::isfinite(options.policy.guard))) {
    throw Error("guard must be finite and >= 0, got " + std::to_string(options.policy.guard));
  }
  if (!(options.correction_rounds == -1 || (options.correction_rounds >= 1 && options.correction_rounds <= 10))) {
    throw Error("correction rounds must be in [1, 10], or -1 for the method's own, got " +
                std::to_string(options.correction_rounds));
  }
  if (!(options.step_extrapolation == -1.0 ||
        (options.step_extrapolation >= 1.0 && options.step_extrapolation <= 100.0))) {
    throw Error("step extrapolation must be in [1, 100] (1 = off), or -1 for the method's own, got " +
                std::to_string(options.step_extrapolation));
  }
  if (!(options.policy.robust_finest_tolerance >= 0.0 && std::isfinite(options.policy.robust_finest_tolerance))) {
    throw Error("robust finest tolerance must be finite and >= 0, got " +
                std::to_string(options.policy.robust_finest_tolerance));
  }
  const double fst = options.policy.robust_finest_step_tolerance;
  if (!(fst == -1.0 || (fst >= 0.0 && std::isfinite(fst)))) {
    throw Error("robust finest step tolerance must be finite and >= 0, or -1 for --step-tolerance, got " +
                std::to_string(fst));
  }
  if (!(options.pixel_motion_tolerance >= 0.0) || !std::isfinite(options.pixel_motion_tolerance)) {
    throw Error("pixel motion tolerance must be finite and >= 0, got " +
                std::to_string(options.pixel_motion_tolerance));
  }
  if (options.problem.threads < 1 || options.problem.threads > 256) {
    throw Error("threads must be in 1..256, got " + std::to_string(options.problem.threads));
  }
  if (options.load_threads < 0 || options.load_threads > io::FrameStream::kMaxLoaders) {
    throw Error("load threads must be in 0.." + std::to_string(io::FrameStream::kMaxLoaders) + " (0: auto), got " +
                std::to_string(options.load_threads));
  }
  if (method == Method::kWeighted && !(options.policy.phi > 0.0 && std::isfinite(options.policy.phi))) {
    throw Error("phi must be finite and > 0, got " + std::to_string(options.policy.phi));
  }
  if (options.first_frame < 0) {
    throw Error("first frame must be >= 0, got " + std::to_string(options.first_frame));
  }
  if (options.max_frames == 0 || options.max_frames == 1 || options.max_frames < -1) {
    throw Error("max frames must be at least 2 (one frame pair) or -1 for all, got " +
                std::to_string(options.max_frames));
  }
}

}  // namespace bivo::odometry
