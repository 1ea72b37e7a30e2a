#pragma once
// Robust per-residual weights (the diagonal of Omega_I / Omega_D, paper eqs. `quadratic
// form`, `depth quadratic`), computed the same way for every method so methods differ only
// in how they combine F_I and F_D.
//
//  * t-distribution (Kerl, Sturm, Cremers, ICRA 2013, default nu = 5): the scale solves
//      sigma^2 = 1/n sum_i r_i^2 (nu + 1) / (nu + r_i^2 / sigma^2)
//    by fixed-point iteration; w_i = (nu + 1) / (nu + r_i^2 / sigma^2).
//  * Huber (k = 1.345 sigma, sigma = 1.4826 * median |r|): w_i = min(1, k sigma / |r_i|).
//  * none: w_i = 1.
//
// The weight stage of RgbdOdometryProblem is split in two: estimate_weight_model() finds the
// scales (the part that needs every residual), and the kernels apply the resulting
// WeightModel term by term, fused into the normal-equation pass (rgbd_kernels.h).
#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "odometry/kernels/kernels.h"

namespace bivo::odometry {

enum class WeightKind { kTDistribution, kHuber, kNone };

// "t" / "tdist", "huber", "none"; unknown -> bivo::Error listing the valid names.
WeightKind parse_weight_kind(const std::string& name);
const char* to_string(WeightKind kind);

struct WeightOptions {
  WeightKind kind = WeightKind::kTDistribution;
  double nu = 5.0;         // degrees of freedom of the t-distribution
  double huber_k = 1.345;  // Huber threshold in units of the robust scale
  int max_scale_iterations = 50;
  double scale_tolerance = 1e-4;  // relative change of sigma^2 that ends the iteration
};

// Fills weights[i] for the residuals with valid[i] != 0 (weights[i] = 0 elsewhere) and
// returns the scale sigma (0 when there are no valid residuals or all are 0; the weights
// are then 1). residuals, valid and weights have the same length. initial_sigma > 0 starts
// the t-distribution's fixed-point iteration there (e.g. the previous iteration's scale).
double compute_weights(const float* residuals, const unsigned char* valid, std::size_t n, const WeightOptions& options,
                       float* weights, double initial_sigma = 0.0);

// What the scale estimation needs to know about one objective's residuals in the buffers
// (invalid terms hold r = 0): the residuals, how many are valid, their sum of squares.
struct ResidualSet {
  const float* r = nullptr;
  const std::uint8_t* flags = nullptr;
  std::uint8_t bit = 1;
  long long valid = 0;
  double sum_squares = 0.0;
};

// The scale of one objective as compute_weights() finds it (same fixed point, same
// conventions), over buffers of `terms` entries with the kernels' chunked sums on `threads`
// threads; initial_sigma warm-starts the t fixed point.
double estimate_scale(const ResidualSet& set, std::size_t terms, const WeightOptions& options, double initial_sigma,
                      const KernelTable& kernels, int threads);

// Both objectives' scales, each exactly as estimate_scale() finds it, with the two
// t fixed points sharing their passes over the buffers (one pass and, with threads, one
// parallel region per step instead of two).
std::array<double, 2> estimate_scales(const ResidualSet& intensity, const ResidualSet& depth, std::size_t terms,
                                      const WeightOptions& options, std::array<double, 2> initial_sigma,
                                      const KernelTable& kernels, int threads);

// The WeightModel that applies `options` with scales sigma_i, sigma_d (0, or a scale whose
// inverse square overflows float: unit weights, the compute_weights() convention for an
// objective without usable residuals).
WeightModel weight_model(const WeightOptions& options, double sigma_i, double sigma_d);

}  // namespace bivo::odometry
