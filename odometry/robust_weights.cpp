#include "odometry/robust_weights.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "odometry/kernels/kernels.h"
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
    case WeightKind::kTDistribution:
      return "tdist";
    case WeightKind::kHuber:
      return "huber";
    case WeightKind::kNone:
      return "none";
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
// does not converge to a positive finite value. One pass at a time (update()), so that the
// two objectives' iterations can share their passes (estimate_scales()).
class ScaleIteration {
 public:
  ScaleIteration(long long count, double sum_squares, const WeightOptions& options, double initial_sigma)
      : count_(count),
        max_iterations_(options.max_scale_iterations),
        tolerance_(options.scale_tolerance),
        sigma2_(initial_sigma > 0.0 ? initial_sigma * initial_sigma : sum_squares / double(count)) {}
  bool running() const { return !stopped_ && iterations_ < max_iterations_; }
  double inv_scale2() const { return 1.0 / sigma2_; }
  void update(const ScaleSums& s) {
    const double g = s.sum / double(count_);
    const double slope = s.slope / (double(count_) * sigma2_);  // g'(sigma^2), in [0, g / sigma^2)
    double next = g;
    if (slope < 0.9) {
      const double newton = sigma2_ + (g - sigma2_) / (1.0 - slope);
      if (newton >= 0.5 * std::min(sigma2_, g) && newton <= 2.0 * std::max(sigma2_, g)) next = newton;
    }
    const bool done = std::abs(next - sigma2_) <= tolerance_ * sigma2_;
    sigma2_ = next;
    ++iterations_;
    if (done || !(sigma2_ > 0.0)) stopped_ = true;
  }
  double sigma() const { return sigma2_ > 0.0 && std::isfinite(sigma2_) ? std::sqrt(sigma2_) : 0.0; }

 private:
  long long count_;
  int max_iterations_;
  double tolerance_;
  double sigma2_;
  int iterations_ = 0;
  bool stopped_ = false;
};

template <class ScaleSumsFn>
double t_fixed_point(const ScaleSumsFn& scale_sums, long long count, double sum_squares, const WeightOptions& options,
                     double initial_sigma) {
  ScaleIteration it(count, sum_squares, options, initial_sigma);
  while (it.running()) it.update(scale_sums(it.inv_scale2()));
  return it.sigma();
}

// A scale that needs no fixed-point iteration: 0 without valid residuals, the RMS for
// unit weights or zero residuals; nullopt when the t fixed point must be run.
std::optional<double> direct_scale(const ResidualSet& set, const WeightOptions& options) {
  if (set.valid == 0) return 0.0;
  const double rms = std::sqrt(set.sum_squares / double(set.valid));
  if (set.sum_squares == 0.0 || options.kind == WeightKind::kNone) return rms;
  return std::nullopt;
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

double compute_weights(const float* residuals, const unsigned char* valid, std::size_t n, const WeightOptions& options,
                       float* weights, double initial_sigma) {
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
  if (const std::optional<double> direct = direct_scale(set, options)) return *direct;
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

std::array<double, 2> estimate_scales(const ResidualSet& intensity, const ResidualSet& depth, std::size_t terms,
                                      const WeightOptions& options, std::array<double, 2> initial_sigma,
                                      const KernelTable& kernels, int threads) {
  const std::optional<double> direct_i = direct_scale(intensity, options), direct_d = direct_scale(depth, options);
  if (direct_i || direct_d || options.kind != WeightKind::kTDistribution) {
    return {estimate_scale(intensity, terms, options, initial_sigma[0], kernels, threads),
            estimate_scale(depth, terms, options, initial_sigma[1], kernels, threads)};
  }
  // Both t fixed points in lockstep: each pass sums both objectives' residuals while both
  // iterate (per chunk the same sums as estimate_scale's, added in the same order).
  struct Pair {
    ScaleSums i, d;
    void add(const Pair& o) {
      i.add(o.i);
      d.add(o.d);
    }
  };
  ScaleIteration it_i(intensity.valid, intensity.sum_squares, options, initial_sigma[0]);
  ScaleIteration it_d(depth.valid, depth.sum_squares, options, initial_sigma[1]);
  const float nu = static_cast<float>(options.nu);
  const std::size_t padded = padded_terms(terms);
  while (it_i.running() || it_d.running()) {
    const bool run_i = it_i.running(), run_d = it_d.running();
    const float inv_i = static_cast<float>(it_i.inv_scale2()), inv_d = static_cast<float>(it_d.inv_scale2());
    const Pair sums = sum_over_chunks<Pair>(padded, kChunkTerms, threads, [&](std::size_t b, std::size_t e) {
      Pair p;
      if (run_i) p.i = kernels.t_scale_sums(intensity.r, b, e, nu, inv_i);
      if (run_d) p.d = kernels.t_scale_sums(depth.r, b, e, nu, inv_d);
      return p;
    });
    if (run_i) it_i.update(sums.i);
    if (run_d) it_d.update(sums.d);
  }
  return {it_i.sigma(), it_d.sigma()};
}

WeightModel weight_model(const WeightOptions& options, double sigma_i, double sigma_d) {
  WeightModel m;
  const auto objective = [&](double sigma) {
    ObjectiveWeights w;  // unit
    // A scale whose inverse square overflows float (residuals that vanish) weighs as none.
    if (!(sigma > 0.0) || !std::isfinite(static_cast<float>(1.0 / (sigma * sigma)))) return w;
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
    case WeightKind::kTDistribution:
      m.kind = WeightModel::kTDistribution;
      break;
    case WeightKind::kHuber:
      m.kind = WeightModel::kHuber;
      break;
    case WeightKind::kNone:
      m.kind = WeightModel::kUnit;
      break;
  }
  m.intensity = objective(sigma_i);
  m.depth = objective(sigma_d);
  return m;
}

}  // namespace bivo::odometry
