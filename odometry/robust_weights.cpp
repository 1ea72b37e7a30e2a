#include "odometry/robust_weights.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "odometry/parallel_chunks.h"
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

namespace {

// The t-distribution's scale: fixed point of sigma^2 = g(sigma^2), g = scale_sums(1 /
// sigma^2).sum / count, started at initial_sigma (or the RMS), by Newton's method on
// g(s) - s = 0 (the same pass gives g'; ScaleSums). The plain fixed-point step g(s) is taken
// instead when g' is near 1 or the Newton step leaves [min(s, g) / 2, 2 max(s, g)]. Newton
// needs ~2-3 passes over the residuals where the plain iteration took ~14 per linearization
// (counted on fr1/rpy). Stops when a step changes sigma^2 by <= scale_tolerance; 0 when it
// does not converge to a positive finite value.
template <class ScaleSumsFn>
double t_fixed_point(const ScaleSumsFn& scale_sums, long long count, double sum_squares, const WeightOptions& options,
                     double initial_sigma) {
  double sigma2 = initial_sigma > 0.0 ? initial_sigma * initial_sigma : sum_squares / double(count);
  for (int it = 0; it < options.max_scale_iterations; ++it) {
    const ScaleSums s = scale_sums(1.0 / sigma2);
    const double g = s.sum / double(count);
    const double slope = s.slope / (double(count) * sigma2);  // g'(sigma^2), in [0, g / sigma^2)
    double next = g;
    if (slope < 0.9) {
      const double newton = sigma2 + (g - sigma2) / (1.0 - slope);
      if (newton >= 0.5 * std::min(sigma2, g) && newton <= 2.0 * std::max(sigma2, g)) next = newton;
    }
    const bool done = std::abs(next - sigma2) <= options.scale_tolerance * sigma2;
    sigma2 = next;
    if (done || !(sigma2 > 0.0)) break;
  }
  if (!(sigma2 > 0.0) || !std::isfinite(sigma2)) return 0.0;
  return std::sqrt(sigma2);
}

// 1.4826 median |r| over the valid residuals (MAD about zero: residuals at the optimum are
// centred); the RMS when the median is 0.
double huber_scale(std::vector<float>& absr, double sum_squares) {
  const std::size_t mid = absr.size() / 2;
  std::nth_element(absr.begin(), absr.begin() + static_cast<std::ptrdiff_t>(mid), absr.end());
  const double sigma = 1.4826 * absr[mid];
  return sigma > 0.0 ? sigma : std::sqrt(sum_squares / double(absr.size()));
}

}  // namespace

double compute_weights(const float* residuals, const unsigned char* valid, std::size_t n,
                       const WeightOptions& options, float* weights, double initial_sigma) {
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
  std::vector<float> v;
  v.reserve(count);
  if (options.kind == WeightKind::kHuber) {
    for (std::size_t i = 0; i < n; ++i) {
      if (valid[i]) v.push_back(std::abs(residuals[i]));
    }
    const double sigma = huber_scale(v, sum_sq);
    const double k = options.huber_k * sigma;
    for (std::size_t i = 0; i < n; ++i) {
      const double a = std::abs(residuals[i]);
      weights[i] = !valid[i] ? 0.0f : a <= k ? 1.0f : static_cast<float>(k / a);
    }
    return sigma;
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (valid[i]) v.push_back(residuals[i]);
  }
  const KernelTable& kernels = default_kernels();
  v.resize(padded_terms(v.size()), 0.0f);
  const float nu = static_cast<float>(options.nu);
  const double sigma = t_fixed_point(
      [&](double inv) { return kernels.t_scale_sums(v.data(), 0, v.size(), nu, static_cast<float>(inv)); },
      static_cast<long long>(count), sum_sq, options, initial_sigma);
  if (sigma == 0.0) {
    fill(1.0f);
    return 0.0;
  }
  const float fnu = nu, fnu1 = static_cast<float>(options.nu + 1.0);
  const float inv = static_cast<float>(1.0 / (sigma * sigma));
  for (std::size_t i = 0; i < n; ++i) {
    const float r = residuals[i];
    weights[i] = valid[i] ? fnu1 / (fnu + r * r * inv) : 0.0f;
  }
  return sigma;
}

double estimate_scale(const ResidualSet& set, std::size_t terms, const WeightOptions& options, double initial_sigma,
                      const KernelTable& kernels, int threads) {
  if (set.valid == 0) return 0.0;
  const double rms = std::sqrt(set.sum_squares / double(set.valid));
  if (set.sum_squares == 0.0 || options.kind == WeightKind::kNone) return rms;
  if (options.kind == WeightKind::kHuber) {
    std::vector<float> absr;
    absr.reserve(static_cast<std::size_t>(set.valid));
    for (std::size_t k = 0; k < terms; ++k) {
      if (set.flags[k] & set.bit) absr.push_back(std::abs(set.r[k]));
    }
    return huber_scale(absr, set.sum_squares);
  }
  const float nu = static_cast<float>(options.nu);
  const std::size_t padded = padded_terms(terms);
  return t_fixed_point(
      [&](double inv) {
        return sum_over_chunks<ScaleSums>(padded, kChunkTerms, threads, [&](std::size_t b, std::size_t e) {
          return kernels.t_scale_sums(set.r, b, e, nu, static_cast<float>(inv));
        });
      },
      set.valid, set.sum_squares, options, initial_sigma);
}

WeightModel weight_model(const WeightOptions& options, double sigma_i, double sigma_d) {
  WeightModel m;
  const auto objective = [&](double sigma) {
    ObjectiveWeights w;  // unit
    if (!(sigma > 0.0)) return w;
    if (options.kind == WeightKind::kTDistribution) {
      w.numerator = static_cast<float>(options.nu + 1.0);
      w.denominator = static_cast<float>(options.nu);
      w.inv_scale2 = static_cast<float>(1.0 / (sigma * sigma));
    } else if (options.kind == WeightKind::kHuber) {
      w.huber = static_cast<float>(options.huber_k * sigma);
    }
    return w;
  };
  switch (options.kind) {
    case WeightKind::kTDistribution: m.kind = WeightModel::kTDistribution; break;
    case WeightKind::kHuber: m.kind = WeightModel::kHuber; break;
    case WeightKind::kNone: m.kind = WeightModel::kUnit; break;
  }
  m.intensity = objective(sigma_i);
  m.depth = objective(sigma_d);
  return m;
}

}  // namespace bivo::odometry
