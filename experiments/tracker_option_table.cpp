// The tracker options' one list and its one check (tracker_option_table.h).
#include "experiments/tracker_option_table.h"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <sstream>

#include "odometry/io/camera_intrinsics.h"
#include "odometry/io/frame_stream.h"
#include "odometry/io/lens_distortion.h"
#include "odometry/odometry_methods.h"
#include "solvers/backend_registry.h"
#include "solvers/error.h"

namespace bivo::experiments {

namespace {

using json = nlohmann::json;
using odometry::TrackerOptions;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kIntMax = std::numeric_limits<int>::max();

// Accessors of a plain field: json converts both ways. Lambdas without captures, so the
// table holds plain function pointers.
#define BIVO_FIELD(member) \
  [](const TrackerOptions& o) -> json { return o.member; }, [](TrackerOptions& o, const json& v) { v.get_to(o.member); }
// An enum field by name (its to_string / parse functions).
#define BIVO_NAMED(member, to_name, parse)                           \
  [](const TrackerOptions& o) -> json { return to_name(o.member); }, \
      [](TrackerOptions& o, const json& v) { o.member = parse(v.get<std::string>()); }

TrackerOption number(std::string key, std::string flag, double lo, double hi, std::string help,
                     json (*get)(const TrackerOptions&), void (*set)(TrackerOptions&, const json&),
                     std::string method = "") {
  TrackerOption o;
  o.key = std::move(key), o.flag = std::move(flag), o.type = OptionType::kNumber, o.lo = lo, o.hi = hi;
  o.help = std::move(help), o.method = std::move(method), o.get = get, o.set = set;
  return o;
}
TrackerOption positive(std::string key, std::string flag, std::string help, json (*get)(const TrackerOptions&),
                       void (*set)(TrackerOptions&, const json&), std::string method = "") {
  TrackerOption o = number(std::move(key), std::move(flag), 0.0, kInf, std::move(help), get, set, std::move(method));
  o.lo_open = true;
  return o;
}
TrackerOption integer(std::string key, std::string flag, double lo, double hi, std::string help,
                      json (*get)(const TrackerOptions&), void (*set)(TrackerOptions&, const json&)) {
  TrackerOption o = number(std::move(key), std::move(flag), lo, hi, std::move(help), get, set);
  o.type = OptionType::kInteger;
  return o;
}
// The option also takes -1: "the method's own" (odometry_methods.h resolves it) or, for the
// readout time and the vignetting, "what the sequence states" (odometry::with_stated_sensor).
TrackerOption or_minus_one(TrackerOption o) {
  o.auto_value = -1.0;
  return o;
}
TrackerOption other(OptionType type, std::string key, std::string flag, std::string help,
                    json (*get)(const TrackerOptions&), void (*set)(TrackerOptions&, const json&)) {
  TrackerOption o = number(std::move(key), std::move(flag), 0.0, 0.0, std::move(help), get, set);
  o.type = type;
  return o;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

std::vector<TrackerOption> build_table() {
  using T = OptionType;
  const std::string max_loaders = std::to_string(odometry::io::FrameStream::kMaxLoaders);
  std::vector<TrackerOption> t = {
      other(T::kString, "method", "--method", "one of: " + join(odometry::method_names()), BIVO_FIELD(method)),
      other(T::kString, "backend", "--backend",
            "solver backend (empty: gn for weighted-sum methods, exact for bounded):\n" + solvers::backend_help(),
            BIVO_FIELD(backend)),
      number("policy.lambda", "--lambda", 0.0, kInf, "the weight lambda of F_I + lambda F_D [gray^2/m^2]",
             BIVO_FIELD(policy.lambda), "fixed"),
      positive("policy.phi", "--phi", "the constant phi of eq. `eq to calculate lambda`", BIVO_FIELD(policy.phi),
               "weighted"),
      number("policy.delta", "--delta", 0.0, kInf, "threshold on pi(D) [m per pixel] of the epsilon rule",
             BIVO_FIELD(policy.delta), "bounded"),
      number("policy.eps_min", "--eps-min", 0.0, kInf, "eps_bar [m^2] on rich structure (pi(D) > delta)",
             BIVO_FIELD(policy.eps_min), "bounded"),
      number("policy.eps_max", "--eps-max", 0.0, kInf, "eps_bar [m^2] on poor structure (pi(D) <= delta)",
             BIVO_FIELD(policy.eps_max), "bounded"),
      number(
          "policy.eps", "--eps", 0.0, kInf,
          "fixed bound on F_D per unit weight [m^2] instead of the pi(D) rule (null: the rule)",
          [](const TrackerOptions& o) -> json { return o.policy.eps ? json(*o.policy.eps) : json(nullptr); },
          [](TrackerOptions& o, const json& v) {
            if (v.is_null()) {
              o.policy.eps.reset();
            } else {
              o.policy.eps = v.get<double>();
            }
          },
          "bounded"),
      number("policy.kappa", "--kappa", 0.0, kInf, "lambda = kappa sigma_I^2 / sigma_D^2 (robust scales)",
             BIVO_FIELD(policy.kappa), "scaled"),
      positive("policy.eps_ratio", "--eps-ratio", "eps_bar / (F_D per unit weight at the photometric solution)",
               BIVO_FIELD(policy.eps_ratio), "noise-bounded"),
      number("policy.guard", "--guard", 0.0, kInf,
             "rise of F_I in units of sigma_I^2 (chi-square-like, 6 dof) beyond which the bound is relaxed",
             BIVO_FIELD(policy.guard), "noise-bounded"),
      or_minus_one(number("policy.joint_tolerance", "--joint-tolerance", 0.0, kInf,
                          "relative merit change that ends a level (instead of --decrease-tolerance; -1: the method's "
                          "own, joint 1e-3, robust 1e-4)",
                          BIVO_FIELD(policy.joint_tolerance), "joint")),
      number("policy.relaxed_tolerance", "--relaxed-tolerance", 0.0, kInf,
             "relative merit change to which a relaxed level's photometric solution is finished",
             BIVO_FIELD(policy.relaxed_tolerance), "noise-bounded"),
      number("policy.trust", "--trust", 0.0, kInf,
             "depth trust statistic (photometric distance of the bi-objective estimate, in sigma_I^2) above "
             "which a level falls back to F_I alone",
             BIVO_FIELD(policy.trust), "robust"),
      number("policy.robust_kappa", "--robust-kappa", 0.0, kInf,
             "lambda = robust_kappa S_II / S_DD (1: joint's balance of the two residuals)",
             BIVO_FIELD(policy.robust_kappa), "robust"),
      number("policy.robust_finest_tolerance", "--robust-finest-tolerance", 0.0, kInf,
             "relative merit change that ends the finest level (--joint-tolerance ends the coarser ones)",
             BIVO_FIELD(policy.robust_finest_tolerance), "robust"),
      or_minus_one(number("policy.robust_finest_step_tolerance", "--robust-finest-step-tolerance", 0.0, kInf,
                          "step norm (m, rad) that ends the finest level (--step-tolerance the coarser ones; -1: "
                          "--step-tolerance there too)",
                          BIVO_FIELD(policy.robust_finest_step_tolerance), "robust")),
      integer("policy.photometric_start_levels", "--photometric-start-levels", -1, 8,
              "methods joint and robust: the coarsest N levels start from F_I's own solution (0: off; -1: "
              "the method's own, 3 for joint, 1 for robust)",
              BIVO_FIELD(policy.photometric_start_levels)),
      integer("policy.both_starts", "--both-starts", 0, 1,
              "methods joint and robust: 1 also solves the photometric start levels from the prior and, where "
              "the two estimates are 0.5 deg or 1 cm apart, keeps the one whose residual scale matrix has the "
              "smaller determinant (0: the photometric start alone)",
              BIVO_FIELD(policy.both_starts)),
      integer("levels", "--levels", 1, 8, "pyramid levels (640x480 down to 640/2^(L-1))", BIVO_FIELD(levels)),
      integer("finest_level", "--finest-level", 0, 7,
              "finest pyramid level solved (0 = full resolution, 1 = half, ...; below --levels)",
              BIVO_FIELD(finest_level)),
      other(T::kName, "initial_guess", "--initial-guess", "identity or constant-velocity",
            BIVO_NAMED(initial_guess, odometry::to_string, odometry::parse_initial_guess)),
      integer("retry_from_rest", "--retry-from-rest", 0, 1,
              "a pair no level could solve from the constant-velocity prior is estimated again from rest, kept "
              "when it aligns the pair as well as the prior (1), or takes the prior (0)",
              BIVO_FIELD(retry_from_rest)),
      integer("max_iterations", "--max-iterations", 1, 100000, "outer iterations per pyramid level",
              BIVO_FIELD(max_iterations)),
      number("step_tolerance", "--step-tolerance", 0.0, kInf, "step norm (m, rad) that ends a level",
             BIVO_FIELD(step_tolerance)),
      number("relative_decrease_tolerance", "--decrease-tolerance", 0.0, kInf,
             "relative merit decrease that ends a level", BIVO_FIELD(relative_decrease_tolerance)),
      number("pixel_motion_tolerance", "--pixel-motion-tolerance", 0.0, kInf,
             "a step moving the reference points' projections by less than this RMS [px] ends a level (0: off)",
             BIVO_FIELD(pixel_motion_tolerance)),
      or_minus_one(number("step_extrapolation", "--step-extrapolation", 1.0, 100.0,
                          "largest factor a Gauss-Newton step that shrinks steadily in one direction is extrapolated "
                          "by, to the limit of its geometric tail (1: off; -1: the method's own, 1.9 for robust, else "
                          "off)",
                          BIVO_FIELD(step_extrapolation))),
      integer("exact_finish_iterations", "--exact-finish-iterations", 0, 1000,
              "with inverse/esm Jacobians, continue the finest level with exact (current-side) gradients for at "
              "most N iterations (0: off)",
              BIVO_FIELD(exact_finish_iterations)),
      integer("retime_depth", "--retime-depth", 0, 1,
              "unsynchronized depth: re-estimate the pair on depth images moved to their colour images' times "
              "with the pair's first estimate (1), or take them as synchronized (0)",
              BIVO_FIELD(retime_depth)),
      or_minus_one(number("readout_time", "--readout-time", 0.0, 1.0,
                          "rolling-shutter readout of the colour images [s]: re-estimate the pair on colour "
                          "images moved to their timestamps (the middle row's) with the pair's first estimate "
                          "(0: global shutter; -1: the readout the sequence states in scene.json, else 0)",
                          BIVO_FIELD(readout_time))),
      or_minus_one(number("vignetting", "--vignetting", 0.0, 0.999,
                          "colour fall-off k of 1 - k rho^2 divided out of every frame; joint then fits no "
                          "fall-off of its own (0: none; -1: the fall-off the sequence states in scene.json, else 0)",
                          BIVO_FIELD(vignetting))),
      or_minus_one(
          integer("correction_rounds", "--correction-rounds", 1, 10,
                  "with frames corrected (--readout-time, --retime-depth): times the pair is estimated "
                  "again on frames corrected with its latest estimate (-1: the method's own, 2 for joint, else 1)",
                  BIVO_FIELD(correction_rounds))),
      other(T::kBoolean, "evaluate_unused_objective", "--evaluate-unused-objective",
            "single/depth: also evaluate the objective not optimized, at each level's end",
            BIVO_FIELD(evaluate_unused_objective)),
      integer("min_valid_pixels", "--min-valid-pixels", 1, kIntMax, "a level with fewer valid terms is skipped",
              BIVO_FIELD(min_valid_pixels)),
      number("max_association_dt", "--max-dt", 0.0, 1e6, "rgb/depth association tolerance [s]",
             BIVO_FIELD(max_association_dt)),
      integer("first_frame", "", 0, kIntMax, "index of the first associated frame processed", BIVO_FIELD(first_frame)),
      integer("max_frames", "", -1, kIntMax, "frames processed from first_frame (-1: to the end)",
              BIVO_FIELD(max_frames)),
      other(T::kBoolean, "start_at_groundtruth", "--start-at-groundtruth",
            "first pose from groundtruth.txt when it covers the first frame", BIVO_FIELD(start_at_groundtruth)),
      other(T::kBoolean, "prefetch_frames", "--prefetch-frames",
            "load the next frame on a thread of its own while a pair is tracked (same results, less wall time; "
            "false: frames load between pairs)",
            BIVO_FIELD(prefetch_frames)),
      integer("load_threads", "--load-threads", 0, odometry::io::FrameStream::kMaxLoaders,
              "with --prefetch-frames: threads decoding frames ahead, one frame each (0 = auto: 2 when the "
              "processors this process may use have a core for each beside --threads, else 1; up to " +
                  max_loaders + "; same results; more than the free cores stretch each pair's wall time)",
              BIVO_FIELD(load_threads)),
      integer("verbosity", "--verbosity", 0, 10, "solver log level", BIVO_FIELD(verbosity)),
      number("problem.min_depth", "--min-depth", 0.0, kInf, "reference depths below this are not used [m]",
             BIVO_FIELD(problem.min_depth)),
      number("problem.max_depth", "--max-depth", 0.0, kInf, "reference depths above this are not used [m]",
             BIVO_FIELD(problem.max_depth)),
      number("problem.occlusion_margin", "--occlusion-margin", 0.0, kInf,
             "a warped point this far behind the current depth is occluded [m]", BIVO_FIELD(problem.occlusion_margin)),
      integer("problem.depth_noise_exponent", "--depth-noise-exponent", -1, 3,
              "r_D divided by (z / 1 m)^p, z the reference depth: 2 for depth noise growing with z^2 "
              "(structured light, stereo), 3 as the real fr3 residual's spread, 0 for noise independent of "
              "depth, -1 the method's own (3 for joint and robust, else 0)",
              BIVO_FIELD(problem.depth_noise_exponent)),
      integer("problem.affine_brightness", "--affine-brightness", -1, 2,
              "1: r_I = I_2 - (a I_1 + b), the brightness change (a, b) refit wherever r_I and r_D are "
              "weighed together (auto-exposure, gain steps; not on F_I alone); 2: also a camera-fixed radial "
              "fall-off, (a + c (rho_2^2 - rho_1^2)) I_1 (vignetting); 0: r_I as defined; -1 the "
              "method's own (2 for joint, 1 for robust, else 0)",
              BIVO_FIELD(problem.affine_brightness)),
      number("problem.radial_prior", "--radial-prior", 0.0, 1e6,
             "with --affine-brightness 2: a ridge toward no fall-off, radial_prior x the sum of the weights x c^2 "
             "joins the fit of c (gray levels^2; 0: c as the data fit it; 0.3 chosen held out for joint)",
             BIVO_FIELD(problem.radial_prior)),
      number("problem.min_valid_fraction", "--min-valid-fraction", 0.0, 1.0,
             "a level whose final pose keeps fewer valid terms than this fraction of its reference terms fails "
             "(a degenerate pose: the level is skipped)",
             BIVO_FIELD(problem.min_valid_fraction)),
      other(T::kBoolean, "problem.depth_first", "", "set by the method (depth)", BIVO_FIELD(problem.depth_first)),
      other(T::kBoolean, "problem.joint_weights", "", "set by the method (joint)", BIVO_FIELD(problem.joint_weights)),
      other(T::kBoolean, "problem.model_f2", "", "set by the method (single/depth: false)",
            BIVO_FIELD(problem.model_f2)),
      other(T::kName, "problem.jacobian", "--jacobian",
            "image gradients of the Jacobians: forward, inverse, esm or auto (the method's default: inverse for "
            "joint, inverse and forward at the finest level for robust, forward otherwise)",
            BIVO_NAMED(problem.jacobian, odometry::to_string, odometry::parse_jacobian_kind)),
      integer("problem.threads", "--threads", 1, 256,
              "threads of the per-pixel passes, the pyramid and the frame moves (results do not depend on it)",
              BIVO_FIELD(problem.threads)),
      other(T::kName, "problem.weights.kind", "--weights", "robust weights: tdist, huber or none",
            BIVO_NAMED(problem.weights.kind, odometry::to_string, odometry::parse_weight_kind)),
      positive("problem.weights.nu", "--nu", "degrees of freedom of the t-distribution weights",
               BIVO_FIELD(problem.weights.nu)),
      positive("problem.weights.huber_k", "--huber-k", "Huber threshold in robust scales",
               BIVO_FIELD(problem.weights.huber_k)),
      integer("problem.weights.max_scale_iterations", "--scale-iterations", 1, 100000,
              "fixed-point iterations of the t-distribution scale", BIVO_FIELD(problem.weights.max_scale_iterations)),
      number("problem.weights.scale_tolerance", "--scale-tolerance", 0.0, kInf,
             "relative change of sigma^2 that ends the scale iteration", BIVO_FIELD(problem.weights.scale_tolerance)),
      other(
          T::kIntrinsics, "intrinsics", "--intrinsics",
          "\"fx fy cx cy\" instead of the preset chosen by the sequence name",
          [](const TrackerOptions& o) -> json {
            if (!o.intrinsics) return nullptr;
            return {
                {"fx", o.intrinsics->fx}, {"fy", o.intrinsics->fy}, {"cx", o.intrinsics->cx}, {"cy", o.intrinsics->cy}};
          },
          [](TrackerOptions& o, const json& v) {
            if (v.is_null()) return o.intrinsics.reset();
            o.intrinsics = odometry::io::Intrinsics{v.at("fx").get<double>(), v.at("fy").get<double>(),
                                                    v.at("cx").get<double>(), v.at("cy").get<double>()};
          }),
      other(
          T::kDistortion, "distortion", "--distortion",
          "\"k1 k2 p1 p2 k3\" or \"none\" instead of the lens distortion preset chosen by the sequence name "
          "(freiburg1/2: TUM's calibration; frames are undistorted at loading)",
          [](const TrackerOptions& o) -> json {
            if (!o.distortion) return nullptr;
            const auto& d = *o.distortion;
            return {{"k1", d.k1}, {"k2", d.k2}, {"p1", d.p1}, {"p2", d.p2}, {"k3", d.k3}};
          },
          [](TrackerOptions& o, const json& v) {
            if (v.is_null()) return o.distortion.reset();
            o.distortion =
                odometry::io::Distortion{v.at("k1").get<double>(), v.at("k2").get<double>(), v.at("p1").get<double>(),
                                         v.at("p2").get<double>(), v.at("k3").get<double>()};
          }),
  };
  for (auto& o : t) {
    if (o.key == "policy.eps") o.type = OptionType::kOptionalNumber;  // null: the pi(D) rule
  }
  return t;
}

#undef BIVO_FIELD
#undef BIVO_NAMED

// A value as shown in a message: arrays and objects by their type only (dumping one nested
// 200,000 deep would recurse through the stack, and a message needs no more).
std::string shown(const json& v) { return v.is_structured() ? std::string("an ") + v.type_name() : v.dump(); }

// The fields of an intrinsics / distortion object: all required, each a finite number.
void check_fields(const TrackerOption& option, const json& value, const std::vector<std::string>& names,
                  const std::vector<double>& lows) {
  if (value.is_null()) return;
  if (!value.is_object()) {
    throw Error(option.key + ": must be null or an object with keys " + join(names) + ", got " + shown(value));
  }
  for (auto it = value.begin(); it != value.end(); ++it) {
    bool known = false;
    for (const auto& n : names) known = known || n == it.key();
    if (!known) throw Error(option.key + ": unknown key '" + it.key() + "' (valid: " + join(names) + ")");
  }
  for (std::size_t k = 0; k < names.size(); ++k) {
    const std::string path = option.key + "." + names[k];
    const auto it = value.find(names[k]);
    if (it == value.end()) throw Error(path + ": missing (give all of " + join(names) + ")");
    if (!it->is_number()) throw Error(path + ": must be a number, got " + shown(*it));
    const double d = it->get<double>();
    if (!std::isfinite(d) || !(d > lows[k])) {
      throw Error(path + ": " + format_option_number(d) + " is outside " +
                  (lows[k] == -kInf ? "(-inf, inf)" : "(" + format_option_number(lows[k]) + ", inf)"));
    }
  }
}

}  // namespace

std::string format_option_number(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

std::string TrackerOption::python_name() const {
  std::string name = flag.empty() ? key : flag.substr(2);
  for (char& c : name) c = (c == '-' || c == '.') ? '_' : c;
  return name;
}

std::string TrackerOption::range_text() const {
  switch (type) {
    case OptionType::kNumber:
    case OptionType::kInteger:
    case OptionType::kOptionalNumber:
      return (auto_value ? format_option_number(*auto_value) + " or " : std::string()) + (lo_open ? "(" : "[") +
             format_option_number(lo) + ", " + format_option_number(hi) + "]";
    case OptionType::kBoolean:
      return "true/false";
    case OptionType::kName:
      return "a name";
    case OptionType::kString:
      return "text";
    case OptionType::kIntrinsics:
      return "fx fy cx cy";
    case OptionType::kDistortion:
      return "k1 k2 p1 p2 k3";
  }
  return "";
}

const std::vector<TrackerOption>& tracker_option_table() {
  static const std::vector<TrackerOption> table = build_table();
  return table;
}

const TrackerOption* find_tracker_option_by_key(const std::string& key) {
  for (const auto& o : tracker_option_table()) {
    if (o.key == key) return &o;
  }
  return nullptr;
}
const TrackerOption* find_tracker_option_by_flag(const std::string& flag) {
  for (const auto& o : tracker_option_table()) {
    if (!o.flag.empty() && o.flag == flag) return &o;
  }
  return nullptr;
}
const TrackerOption* find_tracker_option_by_python_name(const std::string& name) {
  for (const auto& o : tracker_option_table()) {
    if (o.python_name() == name) return &o;
  }
  return nullptr;
}

void apply_tracker_option(const TrackerOption& option, const json& value, TrackerOptions& o) {
  const std::string& key = option.key;
  switch (option.type) {
    case OptionType::kOptionalNumber:
      if (value.is_null()) break;
      [[fallthrough]];
    case OptionType::kNumber: {
      if (!value.is_number()) throw Error(key + ": must be a number, got " + shown(value));
      const double d = value.get<double>();
      if (option.auto_value && d == *option.auto_value) break;
      const bool below = option.lo_open ? !(d > option.lo) : !(d >= option.lo);
      if (!std::isfinite(d) || below || d > option.hi) {
        throw Error(key + ": " + format_option_number(d) + " is outside " + option.range_text());
      }
      break;
    }
    case OptionType::kInteger: {
      if (!value.is_number_integer()) throw Error(key + ": must be an integer, got " + shown(value));
      const bool huge = value.is_number_unsigned() && value.get<std::uint64_t>() > std::uint64_t{INT64_MAX};
      const auto i = huge ? INT64_MAX : value.get<std::int64_t>();
      if (!huge && option.auto_value && static_cast<double>(i) == *option.auto_value) break;
      if (huge || static_cast<double>(i) < option.lo || static_cast<double>(i) > option.hi) {
        throw Error(key + ": " + shown(value) + " is outside " + option.range_text());
      }
      break;
    }
    case OptionType::kBoolean:
      if (!value.is_boolean()) throw Error(key + ": must be true or false, got " + shown(value));
      break;
    case OptionType::kString:
    case OptionType::kName:
      if (!value.is_string()) throw Error(key + ": must be a string, got " + shown(value));
      break;
    case OptionType::kIntrinsics:
      check_fields(option, value, {"fx", "fy", "cx", "cy"}, {0.0, 0.0, -kInf, -kInf});
      break;
    case OptionType::kDistortion:
      check_fields(option, value, {"k1", "k2", "p1", "p2", "k3"}, {-kInf, -kInf, -kInf, -kInf, -kInf});
      break;
  }
  try {
    option.set(o, value);
  } catch (const Error& e) {  // a name the enum's parser refused; its message lists the valid ones
    throw Error(key + ": " + e.what());
  }
}

json tracker_flag_value(const TrackerOption& option, const std::string& text) {
  const auto as_number = [&]() -> json {
    const char* begin = text.c_str();
    char* end = nullptr;
    errno = 0;
    const double d = std::strtod(begin, &end);
    if (text.empty() || end != begin + text.size()) return text;  // refused as "must be a number"
    return d;
  };
  switch (option.type) {
    case OptionType::kNumber:
      return as_number();
    case OptionType::kOptionalNumber:
      return text == "none" || text == "null" ? json(nullptr) : as_number();
    case OptionType::kInteger: {
      std::int64_t i = 0;
      const auto r = std::from_chars(text.data(), text.data() + text.size(), i);
      if (r.ec == std::errc() && r.ptr == text.data() + text.size()) return i;
      return as_number();  // "2.5" or beyond int64: refused as "must be an integer, got 2.5"
    }
    case OptionType::kBoolean:
      if (text == "true" || text == "1" || text == "yes" || text == "on") return true;
      if (text == "false" || text == "0" || text == "no" || text == "off") return false;
      return text;
    case OptionType::kString:
    case OptionType::kName:
      return text;
    case OptionType::kIntrinsics:
    case OptionType::kDistortion: {
      // Words in the object's key order; apply_tracker_option checks them as the file's.
      const std::vector<std::string> names = option.type == OptionType::kIntrinsics
                                                 ? std::vector<std::string>{"fx", "fy", "cx", "cy"}
                                                 : std::vector<std::string>{"k1", "k2", "p1", "p2", "k3"};
      if (option.type == OptionType::kDistortion && text == "none") {
        return {{"k1", 0.0}, {"k2", 0.0}, {"p1", 0.0}, {"p2", 0.0}, {"k3", 0.0}};
      }
      std::istringstream words(text);
      std::vector<std::string> w;
      for (std::string x; words >> x;) w.push_back(x);
      if (w.size() != names.size()) return text;  // refused as "must be null or an object with keys ..."
      json object = json::object();
      for (std::size_t k = 0; k < names.size(); ++k) {
        TrackerOption number_option;
        number_option.type = OptionType::kNumber;
        object[names[k]] = tracker_flag_value(number_option, w[k]);
      }
      return object;
    }
  }
  return text;
}

}  // namespace bivo::experiments
