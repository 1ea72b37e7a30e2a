// One flag per TrackerOptions field, plus --config (tracker_flags.h).
#include "experiments/cli/tracker_flags.h"

#include "experiments/tracker_config.h"
#include "odometry/io/camera_intrinsics.h"
#include "odometry/io/frame_stream.h"
#include "odometry/io/lens_distortion.h"
#include "odometry/odometry_methods.h"
#include "solvers/backend_registry.h"
#include "solvers/error.h"

namespace bivo::experiments::cli {

namespace {

using odometry::TrackerOptions;

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

}  // namespace

template <class T>
CLI::Option* TrackerFlags::add(const std::string& name, const std::string& help, T initial,
                               std::function<void(TrackerOptions&, const T&)> set) {
  auto value = std::make_shared<T>(std::move(initial));
  CLI::Option* option = cmd_->add_option(name, *value, help)->capture_default_str();
  flags_.push_back({option, [value, set](TrackerOptions& o) { set(o, *value); }});
  return option;
}

TrackerFlags::TrackerFlags(CLI::App* cmd, bool with_method) : cmd_(cmd), with_method_(with_method) {
  const TrackerOptions d;
  const auto& w = d.problem.weights;
  cmd->add_option("--config", *config_,
                  "tracker configuration (JSON, as written next to every result); flags given as well override it")
      ->check(CLI::ExistingFile);
  if (with_method) {
    method_ = add<std::string>("--method", "one of: " + join(odometry::method_names()) + " (default " + d.method + ")",
                     d.method, [](TrackerOptions& o, const std::string& v) { o.method = v; });
    add<std::string>("--backend",
                     "solver backend (default: gn for weighted-sum methods, exact for bounded):\n" +
                         solvers::backend_help(),
                     d.backend, [](TrackerOptions& o, const std::string& v) { o.backend = v; });
    lambda_ = add<double>("--lambda", "method fixed: the weight lambda of F_I + lambda F_D [gray^2/m^2]",
                          d.policy.lambda, [](TrackerOptions& o, const double& v) { o.policy.lambda = v; });
    phi_ = add<double>("--phi", "method weighted: the constant phi of eq. `eq to calculate lambda`", d.policy.phi,
                       [](TrackerOptions& o, const double& v) { o.policy.phi = v; });
    delta_ = add<double>("--delta", "method bounded: threshold on pi(D) [m per pixel] of the epsilon rule",
                         d.policy.delta, [](TrackerOptions& o, const double& v) { o.policy.delta = v; });
    eps_min_ = add<double>("--eps-min", "method bounded: eps_bar [m^2] on rich structure (pi(D) > delta)",
                           d.policy.eps_min, [](TrackerOptions& o, const double& v) { o.policy.eps_min = v; });
    eps_max_ = add<double>("--eps-max", "method bounded: eps_bar [m^2] on poor structure (pi(D) <= delta)",
                           d.policy.eps_max, [](TrackerOptions& o, const double& v) { o.policy.eps_max = v; });
    eps_ = add<double>("--eps", "method bounded: fixed bound on F_D per unit weight [m^2] instead of the pi(D) rule",
                       0.0, [](TrackerOptions& o, const double& v) { o.policy.eps = v; });
    kappa_ = add<double>("--kappa", "method scaled: lambda = kappa sigma_I^2 / sigma_D^2 (robust scales)",
                         d.policy.kappa, [](TrackerOptions& o, const double& v) { o.policy.kappa = v; });
    eps_ratio_ = add<double>("--eps-ratio",
                             "method noise-bounded: eps_bar / (F_D per unit weight at the photometric solution)",
                             d.policy.eps_ratio, [](TrackerOptions& o, const double& v) { o.policy.eps_ratio = v; });
    joint_tolerance_ = add<double>(
        "--joint-tolerance", "method joint: relative merit change that ends a level (instead of --decrease-tolerance)",
        d.policy.joint_tolerance, [](TrackerOptions& o, const double& v) { o.policy.joint_tolerance = v; });
    relaxed_tolerance_ = add<double>(
        "--relaxed-tolerance",
        "method noise-bounded: relative merit change to which a relaxed level's photometric solution is finished",
        d.policy.relaxed_tolerance, [](TrackerOptions& o, const double& v) { o.policy.relaxed_tolerance = v; });
    guard_ = add<double>("--guard", "method noise-bounded: rise of F_I in units of sigma_I^2 (chi-square-like, 6 dof) beyond which the bound is relaxed",
                         d.policy.guard, [](TrackerOptions& o, const double& v) { o.policy.guard = v; });
    add<int>("--photometric-start-levels",
             "methods joint, robust: the coarsest N levels start from F_I's own solution (0: off)",
             d.policy.photometric_start_levels,
             [](TrackerOptions& o, const int& v) { o.policy.photometric_start_levels = v; });
    trust_ = add<double>("--trust",
                         "method robust: depth trust statistic (photometric distance of the bi-objective estimate, "
                         "in sigma_I^2) above which a level falls back to F_I alone",
                         d.policy.trust, [](TrackerOptions& o, const double& v) { o.policy.trust = v; });
  }
  add<int>("--levels", "pyramid levels (640x480 down to 640/2^(L-1))", d.levels,
           [](TrackerOptions& o, const int& v) { o.levels = v; });
  add<int>("--finest-level", "finest pyramid level solved (0 = full resolution, 1 = half, ...)", d.finest_level,
           [](TrackerOptions& o, const int& v) { o.finest_level = v; });
  add<std::string>("--initial-guess", "identity or constant-velocity", odometry::to_string(d.initial_guess),
                   [](TrackerOptions& o, const std::string& v) { o.initial_guess = odometry::parse_initial_guess(v); });
  add<int>("--max-iterations", "outer iterations per pyramid level", d.max_iterations,
           [](TrackerOptions& o, const int& v) { o.max_iterations = v; });
  add<double>("--step-tolerance", "step norm (m, rad) that ends a level", d.step_tolerance,
              [](TrackerOptions& o, const double& v) { o.step_tolerance = v; });
  add<double>("--pixel-motion-tolerance",
              "a step moving the reference points' projections by less than this RMS [px] ends a level (0: off)",
              d.pixel_motion_tolerance, [](TrackerOptions& o, const double& v) { o.pixel_motion_tolerance = v; });
  add<double>("--step-extrapolation",
              "largest factor a Gauss-Newton step that shrinks steadily in one direction is extrapolated by, to the "
              "limit of its geometric tail (1: off)",
              d.step_extrapolation, [](TrackerOptions& o, const double& v) { o.step_extrapolation = v; });
  add<int>("--exact-finish-iterations",
           "with inverse/esm Jacobians, continue the finest level with exact (current-side) gradients for at most N "
           "iterations (0: off)",
           d.exact_finish_iterations, [](TrackerOptions& o, const int& v) { o.exact_finish_iterations = v; });
  add<bool>("--evaluate-unused-objective",
            "single/depth: also evaluate the objective not optimized, at each level's end (true/false)",
            d.evaluate_unused_objective,
            [](TrackerOptions& o, const bool& v) { o.evaluate_unused_objective = v; });
  add<std::string>("--jacobian", "image gradients of the Jacobians: forward, inverse, esm or auto (the method's default: inverse for joint, forward otherwise)",
                   odometry::to_string(d.problem.jacobian),
                   [](TrackerOptions& o, const std::string& v) { o.problem.jacobian = odometry::parse_jacobian_kind(v); });
  add<int>("--threads", "threads of the per-pixel passes and the pyramid (results do not depend on it)",
           d.problem.threads, [](TrackerOptions& o, const int& v) { o.problem.threads = v; });
  add<double>("--decrease-tolerance", "relative merit decrease that ends a level", d.relative_decrease_tolerance,
              [](TrackerOptions& o, const double& v) { o.relative_decrease_tolerance = v; });
  add<int>("--min-valid-pixels", "a level with fewer valid terms is skipped", d.min_valid_pixels,
           [](TrackerOptions& o, const int& v) { o.min_valid_pixels = v; });
  add<std::string>("--weights", "robust weights: tdist, huber or none", odometry::to_string(w.kind),
                   [](TrackerOptions& o, const std::string& v) { o.problem.weights.kind = odometry::parse_weight_kind(v); });
  add<double>("--nu", "degrees of freedom of the t-distribution weights", w.nu,
              [](TrackerOptions& o, const double& v) { o.problem.weights.nu = v; });
  add<double>("--huber-k", "Huber threshold in robust scales", w.huber_k,
              [](TrackerOptions& o, const double& v) { o.problem.weights.huber_k = v; });
  add<int>("--scale-iterations", "fixed-point iterations of the t-distribution scale", w.max_scale_iterations,
           [](TrackerOptions& o, const int& v) { o.problem.weights.max_scale_iterations = v; });
  add<double>("--scale-tolerance", "relative change of sigma^2 that ends the scale iteration", w.scale_tolerance,
              [](TrackerOptions& o, const double& v) { o.problem.weights.scale_tolerance = v; });
  add<double>("--min-depth", "reference depths below this are not used [m]", d.problem.min_depth,
              [](TrackerOptions& o, const double& v) { o.problem.min_depth = v; });
  add<double>("--max-depth", "reference depths above this are not used [m]", d.problem.max_depth,
              [](TrackerOptions& o, const double& v) { o.problem.max_depth = v; });
  add<double>("--occlusion-margin", "a warped point this far behind the current depth is occluded [m]",
              d.problem.occlusion_margin, [](TrackerOptions& o, const double& v) { o.problem.occlusion_margin = v; });
  add<double>("--max-dt", "rgb/depth association tolerance [s]", d.max_association_dt,
              [](TrackerOptions& o, const double& v) { o.max_association_dt = v; });
  add<std::string>("--intrinsics", "\"fx fy cx cy\" instead of the preset chosen by the sequence name", "",
                   [](TrackerOptions& o, const std::string& v) { o.intrinsics = odometry::io::parse_intrinsics(v); });
  add<std::string>("--distortion",
                   "\"k1 k2 p1 p2 k3\" or \"none\" instead of the lens distortion preset chosen by the sequence name "
                   "(freiburg1/2: TUM's calibration; frames are undistorted at loading)",
                   "", [](TrackerOptions& o, const std::string& v) { o.distortion = odometry::io::parse_distortion(v); });
  add<bool>("--start-at-groundtruth", "first pose from groundtruth.txt when it covers the first frame (true/false)",
            d.start_at_groundtruth, [](TrackerOptions& o, const bool& v) { o.start_at_groundtruth = v; });
  add<bool>("--prefetch-frames",
            "load the next frame on a thread of its own while a pair is tracked (true/false; same results, "
            "less wall time; false: frames load between pairs)",
            d.prefetch_frames, [](TrackerOptions& o, const bool& v) { o.prefetch_frames = v; });
  add<int>("--load-threads",
           "with --prefetch-frames: threads decoding frames ahead, one frame each (0 = auto: 2 when the "
           "processors this process may use have a core for each beside --threads, else 1; up to " +
               std::to_string(odometry::io::FrameStream::kMaxLoaders) +
               "; same results; more than the free cores stretch each pair's wall time)",
           d.load_threads, [](TrackerOptions& o, const int& v) { o.load_threads = v; });
  add<int>("--verbosity", "solver log level", d.verbosity, [](TrackerOptions& o, const int& v) { o.verbosity = v; });
}

TrackerOptions TrackerFlags::options() const {
  TrackerOptions o = config_->empty() ? TrackerOptions{} : read_tracker_config(*config_);
  for (const auto& f : flags_) {
    if (f.option->count() == 0) continue;
    try {
      f.apply(o);
    } catch (const Error& e) {
      throw Error(f.option->get_name() + ": " + e.what());
    }
  }
  if (with_method_) {
    if (config_->empty() && method_->count() == 0) {
      throw Error("give --method (or a --config file that names one)");
    }
    const odometry::Method method = odometry::parse_method(o.method);
    auto only_for = [&](const CLI::Option* flag, odometry::Method m) {
      if (flag->count() > 0 && method != m) {
        throw Error(flag->get_name() + " applies to method '" + odometry::to_string(m) + "' only (method is '" +
                    o.method + "')");
      }
    };
    only_for(lambda_, odometry::Method::kFixed);
    only_for(phi_, odometry::Method::kWeighted);
    only_for(eps_, odometry::Method::kBounded);
    only_for(delta_, odometry::Method::kBounded);
    only_for(eps_min_, odometry::Method::kBounded);
    only_for(eps_max_, odometry::Method::kBounded);
    only_for(kappa_, odometry::Method::kScaled);
    only_for(eps_ratio_, odometry::Method::kNoiseBounded);
    only_for(guard_, odometry::Method::kNoiseBounded);
    only_for(joint_tolerance_, odometry::Method::kJoint);
    only_for(relaxed_tolerance_, odometry::Method::kNoiseBounded);
    only_for(trust_, odometry::Method::kRobust);
  }
  odometry::validate(o);
  return o;
}

}  // namespace bivo::experiments::cli
