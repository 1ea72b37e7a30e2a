#include "odometry/robust_weights.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "solvers/error.h"

namespace bivo::odometry {

WeightKind parse_weight_kind(const std::string& name) {
  if (name == "t" || name == "tdist" || name == "t-distribution") return WeightKind::kTDistribution;
  if (name == "huber") return WeightKind::kHuber;
  if (name == "none") return WeightKind::kNone;
  throw Error("unknown weight function '" + name + "' (valid: tdist, huber, none)");
}

const char* to_string(WeightKind kind) {
  switch (kind) {
    case WeightKind::kTDistribution: return "tdist";
    case WeightKind::kHuber: return "huber";
    case WeightKind::kNone: return "none";
  }
  return "?";
}

double compute_weights(const float* residuals, const unsigned char* valid, std::size_t n,
                       const WeightOptions& options, float* weights) {
  double sum_sq = 0.0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (valid[i]) {
      sum_sq += double(residuals[i]) * residuals[i];
      ++count;
    }
  }
  const auto fill = [&](float value) {
    for (std::size_t i = 0; i < n; ++i) weights[i] = valid[i] ? value : 0.0f;
  };
  if (count == 0 || sum_sq == 0.0 || options.kind == WeightKind::kNone) {
    fill(1.0f);
    return count == 0 ? 0.0 : std::sqrt(sum_sq / count);
  }

  if (options.kind == WeightKind::kHuber) {
    std::vector<float> absr;
    absr.reserve(count);
    for (std::size_t i = 0; i < n; ++i) {
      if (valid[i]) absr.push_back(std::abs(residuals[i]));
    }
    const std::size_t mid = absr.size() / 2;
    std::nth_element(absr.begin(), absr.begin() + mid, absr.end());
    double sigma = 1.4826 * absr[mid];  // MAD about zero: residuals at the optimum are centred
    if (sigma <= 0.0) sigma = std::sqrt(sum_sq / count);
    const double k = options.huber_k * sigma;
    for (std::size_t i = 0; i < n; ++i) {
      if (!valid[i]) {
        weights[i] = 0.0f;
        continue;
      }
      const double a = std::abs(residuals[i]);
      weights[i] = a <= k ? 1.0f : static_cast<float>(k / a);
    }
    return sigma;
  }

  // t-distribution: fixed point of sigma^2 = mean(r^2 (nu+1)/(nu + r^2/sigma^2)).
  const double nu = options.nu;
  double sigma2 = sum_sq / count;
  for (int it = 0; it < options.max_scale_iterations; ++it) {
    const double inv = 1.0 / sigma2;
    double acc = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      if (!valid[i]) continue;
      const double r2 = double(residuals[i]) * residuals[i];
      acc += r2 * (nu + 1.0) / (nu + r2 * inv);
    }
    const double next = acc / count;
    const bool done = std::abs(next - sigma2) <= options.scale_tolerance * sigma2;
    sigma2 = next;
    if (done || !(sigma2 > 0.0)) break;
  }
  if (!(sigma2 > 0.0) || !std::isfinite(sigma2)) {
    fill(1.0f);
    return 0.0;
  }
  const double inv = 1.0 / sigma2;
  for (std::size_t i = 0; i < n; ++i) {
    if (!valid[i]) {
      weights[i] = 0.0f;
      continue;
    }
    const double r2 = double(residuals[i]) * residuals[i];
    weights[i] = static_cast<float>((nu + 1.0) / (nu + r2 * inv));
  }
  return std::sqrt(sigma2);
}

}  // namespace bivo::odometry
