#include "odometry/odometry_methods.h"

#include <cmath>
#include <sstream>

#include "odometry/rgbd_problem.h"
#include "solvers/error.h"

namespace bivo::odometry {
namespace {

struct MethodName {
  Method method;
  const char* name;
};
constexpr MethodName kMethods[] = {
    {Method::kSingle, "single"},   {Method::kDepth, "depth"},       {Method::kFixed, "fixed"},
    {Method::kTykkala, "tykkala"}, {Method::kWeighted, "weighted"}, {Method::kBounded, "bounded"},
    {Method::kJoint, "joint"},     {Method::kScaled, "scaled"},     {Method::kNoiseBounded, "noise-bounded"},
    {Method::kRobust, "robust"}};

// The statistics a policy value came from, for messages.
std::string statistics_text(const FrameStatistics& s) {
  std::ostringstream m;
  m << "pi(I) = " << s.pi_intensity << ", pi(D) = " << s.pi_depth << ", var(I) = " << s.var_intensity
    << ", var(D) = " << s.var_depth;
  if (s.has_medians) m << ", median(I) = " << s.median_intensity << ", median(D) = " << s.median_depth;
  return m.str();
}

// value when finite and >= 0; otherwise nullopt and `why` says what and from which statistics.
std::optional<double> defined(double value, const char* what, const FrameStatistics& s, std::string* why) {
  if (std::isfinite(value) && value >= 0.0) return value;
  if (why) {
    std::ostringstream m;
    m << what << " is " << value << " (" << statistics_text(s) << ")";
    *why = m.str();
  }
  return std::nullopt;
}

double checked(double value, const char* what, const FrameStatistics& s) {
  std::string why;
  if (const auto v = defined(value, what, s, &why)) return *v;
  throw Error(why);
}

constexpr const char* kTykkalaWhat = "Tykkala's lambda |median(I)/median(D)|^2";
constexpr const char* kAdaptiveWhat = "adaptive lambda phi gamma^2 pi(D)^2 / pi(I)^2";

double tykkala_formula(const FrameStatistics& s) {
  if (!s.has_medians) throw Error("Tykkala's lambda needs the frame's medians; they were not computed (add_medians())");
  const double ratio = s.median_intensity / s.median_depth;
  return ratio * ratio;
}

double adaptive_formula(const FrameStatistics& s, double phi) {
  const double gamma = s.var_intensity / s.var_depth;
  const double ratio = gamma * s.pi_depth / s.pi_intensity;
  return phi * ratio * ratio;
}

}  // namespace

Method parse_method(const std::string& name) {
  for (const auto& m : kMethods) {
    if (name == m.name) return m.method;
  }
  std::string valid;
  for (const auto& m : kMethods) valid += std::string(valid.empty() ? "" : ", ") + m.name;
  throw Error("unknown method '" + name + "' (valid: " + valid + ")");
}

const char* to_string(Method method) {
  for (const auto& m : kMethods) {
    if (m.method == method) return m.name;
  }
  return "?";
}

std::vector<std::string> method_names() {
  std::vector<std::string> out;
  for (const auto& m : kMethods) out.emplace_back(m.name);
  return out;
}

bool is_bounded(Method method) { return method == Method::kBounded || method == Method::kNoiseBounded; }

bool lambda_from_residuals(Method method) { return method == Method::kJoint || method == Method::kScaled; }

bool uses_joint_weights(Method method) { return method == Method::kJoint || method == Method::kRobust; }

std::string default_backend(Method method) { return is_bounded(method) ? "exact" : "gn"; }

bool reads_medians(Method method) { return method == Method::kTykkala; }

bool reads_frame_statistics(Method method) { return method == Method::kWeighted || method == Method::kBounded; }

double tykkala_lambda(const FrameStatistics& s) { return checked(tykkala_formula(s), kTykkalaWhat, s); }

double adaptive_lambda(const FrameStatistics& s, double phi) {
  return checked(adaptive_formula(s, phi), kAdaptiveWhat, s);
}

double bounded_epsilon_per_weight(const FrameStatistics& s, const PolicyParameters& p) {
  if (p.eps) return checked(*p.eps, "epsilon per unit weight", s);
  return s.pi_depth <= p.delta ? p.eps_max : p.eps_min;
}

std::optional<double> frame_lambda(Method method, const FrameStatistics& s, const PolicyParameters& p,
                                   std::string* why) {
  switch (method) {
    case Method::kSingle:
    case Method::kDepth:
      return 0.0;
    case Method::kFixed:
      return defined(p.lambda, "fixed lambda", s, why);
    case Method::kTykkala:
      return defined(tykkala_formula(s), kTykkalaWhat, s, why);
    case Method::kWeighted:
      return defined(adaptive_formula(s, p.phi), kAdaptiveWhat, s, why);
    case Method::kJoint:
    case Method::kScaled:
    case Method::kRobust:
      throw Error(std::string("method '") + to_string(method) +
                  "' has no per-frame lambda (it is estimated at every linearization from the residuals)");
    case Method::kBounded:
    case Method::kNoiseBounded:
      break;
  }
  throw Error(std::string("method '") + to_string(method) + "' has no lambda (it bounds F_D instead)");
}

double method_lambda(Method method, const FrameStatistics& s, const PolicyParameters& p) {
  std::string why;
  if (const auto lambda = frame_lambda(method, s, p, &why)) return *lambda;
  throw Error(why);
}

double residual_lambda(Method method, const RgbdLinearizationStats& stats, const PolicyParameters& p) {
  if (method == Method::kJoint) return stats.joint_scale.implied_lambda();
  if (method == Method::kRobust) return p.robust_kappa * stats.joint_scale.implied_lambda();
  if (method == Method::kScaled) {
    const double si = stats.sigma_intensity, sd = stats.sigma_depth;
    return sd > 0.0 && std::isfinite(si) ? p.kappa * (si * si) / (sd * sd) : 0.0;
  }
  throw Error(std::string("method '") + to_string(method) + "' does not take lambda from the residuals");
}

JacobianKind method_jacobian(Method method, JacobianKind requested, bool finest_level) {
  if (requested != JacobianKind::kMethodDefault) return requested;
  if (method == Method::kRobust && finest_level) return JacobianKind::kForward;
  return uses_joint_weights(method) ? JacobianKind::kInverse : JacobianKind::kForward;
}

int method_depth_noise_exponent(Method method, int requested) {
  if (requested >= 0) return requested;
  return uses_joint_weights(method) ? 3 : 0;
}

int method_affine_brightness(Method method, int requested, bool falloff_divided_out) {
  if (requested >= 0) return requested;
  if (method == Method::kJoint) return falloff_divided_out ? 1 : 2;
  return method == Method::kRobust ? 1 : 0;
}

double method_joint_tolerance(Method method, double requested) {
  if (requested >= 0.0) return requested;
  if (method == Method::kJoint) return 1e-3;
  return method == Method::kRobust ? 1e-4 : 1e-5;
}

int method_correction_rounds(Method method, int requested) {
  if (requested >= 1) return requested;
  return method == Method::kJoint ? 2 : 1;
}

int method_photometric_start_levels(Method method, int requested) {
  if (requested >= 0) return requested;
  return method == Method::kJoint ? 3 : 1;
}

double method_step_extrapolation(Method method, double requested) {
  if (requested != -1.0) return requested;
  return method == Method::kRobust ? 1.9 : 1.0;
}

}  // namespace bivo::odometry
