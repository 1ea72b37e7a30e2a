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
constexpr MethodName kMethods[] = {{Method::kSingle, "single"},   {Method::kDepth, "depth"},
                                   {Method::kFixed, "fixed"},     {Method::kTykkala, "tykkala"},
                                   {Method::kWeighted, "weighted"}, {Method::kBounded, "bounded"},
                                   {Method::kJoint, "joint"},       {Method::kScaled, "scaled"},
                                   {Method::kNoiseBounded, "noise-bounded"}};

double checked(double value, const char* what, const FrameStatistics& s) {
  if (!std::isfinite(value) || value < 0.0) {
    std::ostringstream m;
    m << what << " is " << value << " (pi(I) = " << s.pi_intensity << ", pi(D) = " << s.pi_depth
      << ", var(I) = " << s.var_intensity << ", var(D) = " << s.var_depth << ", median(I) = " << s.median_intensity
      << ", median(D) = " << s.median_depth << ")";
    throw Error(m.str());
  }
  return value;
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

std::string default_backend(Method method) { return is_bounded(method) ? "exact" : "gn"; }

double tykkala_lambda(const FrameStatistics& s) {
  const double ratio = s.median_intensity / s.median_depth;
  return checked(ratio * ratio, "Tykkala's lambda |median(I)/median(D)|^2", s);
}

double adaptive_lambda(const FrameStatistics& s, double phi) {
  const double gamma = s.var_intensity / s.var_depth;
  const double ratio = gamma * s.pi_depth / s.pi_intensity;
  return checked(phi * ratio * ratio, "adaptive lambda phi gamma^2 pi(D)^2 / pi(I)^2", s);
}

double bounded_epsilon_per_weight(const FrameStatistics& s, const PolicyParameters& p) {
  if (p.eps) return checked(*p.eps, "epsilon per unit weight", s);
  return s.pi_depth <= p.delta ? p.eps_max : p.eps_min;
}

double method_lambda(Method method, const FrameStatistics& s, const PolicyParameters& p) {
  switch (method) {
    case Method::kSingle:
    case Method::kDepth: return 0.0;
    case Method::kFixed: return checked(p.lambda, "fixed lambda", s);
    case Method::kTykkala: return tykkala_lambda(s);
    case Method::kWeighted: return adaptive_lambda(s, p.phi);
    case Method::kJoint:
    case Method::kScaled:
      throw Error(std::string("method '") + to_string(method) +
                  "' has no per-frame lambda (it is estimated at every linearization from the residuals)");
    case Method::kBounded:
    case Method::kNoiseBounded: break;
  }
  throw Error(std::string("method '") + to_string(method) + "' has no lambda (it bounds F_D instead)");
}

double residual_lambda(Method method, const RgbdLinearizationStats& stats, const PolicyParameters& p) {
  if (method == Method::kJoint) return stats.joint_scale.implied_lambda();
  if (method == Method::kScaled) {
    const double si = stats.sigma_intensity, sd = stats.sigma_depth;
    return sd > 0.0 && std::isfinite(si) ? p.kappa * (si * si) / (sd * sd) : 0.0;
  }
  throw Error(std::string("method '") + to_string(method) + "' does not take lambda from the residuals");
}

}  // namespace bivo::odometry
