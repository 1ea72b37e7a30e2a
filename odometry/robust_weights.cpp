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

namespace {

// sum_i r2_i (nu + 1) / (nu + r2_i * inv), in float with eight independent partial sums so
// the compiler can vectorize it without reassociation flags; blocks are summed in double.
double t_scale_sum(const std::vector<float>& r2, double nu, double inv) {
  const float fnu = static_cast<float>(nu), fnu1 = static_cast<float>(nu + 1.0), finv = static_cast<float>(inv);
  double total = 0.0;
  const std::size_t n = r2.size();
  constexpr std::size_t kBlock = 4096;
  for (std::size_t start = 0; start < n; start += kBlock) {
    const std::size_t end = std::min(n, start + kBlock);
    float acc[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    std::size_t i = start;
    for (; i + 8 <= end; i += 8) {
      for (int l = 0; l < 8; ++l) {
        const float v = r2[i + l];
        acc[l] += v * fnu1 / (fnu + v * finv);
      }
    }
    double block = 0.0;
    for (; i < end; ++i) block += double(r2[i]) * fnu1 / (fnu + r2[i] * finv);
    for (float a : acc) block += a;
    total += block;
  }
  return total;
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
  std::vector<float> r2;
  r2.reserve(count);
  for (std::size_t i = 0; i < n; ++i) {
    if (valid[i]) r2.push_back(residuals[i] * residuals[i]);
  }
  const double nu = options.nu;
  double sigma2 = initial_sigma > 0.0 ? initial_sigma * initial_sigma : sum_sq / count;
  for (int it = 0; it < options.max_scale_iterations; ++it) {
    const double next = t_scale_sum(r2, nu, 1.0 / sigma2) / count;
    const bool done = std::abs(next - sigma2) <= options.scale_tolerance * sigma2;
    sigma2 = next;
    if (done || !(sigma2 > 0.0)) break;
  }
  if (!(sigma2 > 0.0) || !std::isfinite(sigma2)) {
    fill(1.0f);
    return 0.0;
  }
  const float fnu = static_cast<float>(nu), fnu1 = static_cast<float>(nu + 1.0);
  const float inv = static_cast<float>(1.0 / sigma2);
  for (std::size_t i = 0; i < n; ++i) {
    const float r = residuals[i];
    weights[i] = valid[i] ? fnu1 / (fnu + r * r * inv) : 0.0f;
  }
  return std::sqrt(sigma2);
}

}  // namespace bivo::odometry
