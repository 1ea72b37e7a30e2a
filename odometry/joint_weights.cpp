#include "odometry/joint_weights.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace bivo::odometry {

double JointScale::correlation() const { return valid() ? s_id / std::sqrt(s_ii * s_dd) : 0.0; }

double JointScale::implied_lambda() const { return valid() ? s_ii / s_dd : 0.0; }

namespace {

// One fixed-point step: the weighted second moments 1/n sum w r r^T with w from S. Float
// with eight independent partial sums per block (vectorizable), blocks summed in double.
JointScale weighted_moments(const std::vector<float>& u, const std::vector<float>& v, double nu, const JointScale& s) {
  const double det = s.s_ii * s.s_dd - s.s_id * s.s_id;
  const float a = static_cast<float>(s.s_dd / det), b = static_cast<float>(-s.s_id / det),
              c = static_cast<float>(s.s_ii / det);
  const float fnu = static_cast<float>(nu), fnu2 = static_cast<float>(nu + 2.0);
  const std::size_t n = u.size();
  double suu = 0.0, suv = 0.0, svv = 0.0;
  constexpr std::size_t kBlock = 4096;
  for (std::size_t start = 0; start < n; start += kBlock) {
    const std::size_t end = std::min(n, start + kBlock);
    float acc_uu[8] = {}, acc_uv[8] = {}, acc_vv[8] = {};
    std::size_t i = start;
    for (; i + 8 <= end; i += 8) {
      for (int l = 0; l < 8; ++l) {
        const float x = u[i + l], y = v[i + l];
        const float w = fnu2 / (fnu + a * x * x + 2.0f * b * x * y + c * y * y);
        acc_uu[l] += w * x * x;
        acc_uv[l] += w * x * y;
        acc_vv[l] += w * y * y;
      }
    }
    for (; i < end; ++i) {
      const float x = u[i], y = v[i];
      const float w = fnu2 / (fnu + a * x * x + 2.0f * b * x * y + c * y * y);
      suu += double(w) * x * x;
      suv += double(w) * x * y;
      svv += double(w) * y * y;
    }
    for (int l = 0; l < 8; ++l) {
      suu += acc_uu[l];
      suv += acc_uv[l];
      svv += acc_vv[l];
    }
  }
  const double inv_n = 1.0 / static_cast<double>(n);
  return {suu * inv_n, suv * inv_n, svv * inv_n};
}

// The estimator for any validity encoding: valid_i(k), valid_d(k) say whether r_I,k, r_D,k count.
template <class ValidI, class ValidD>
JointScale joint_weights(const float* r_i, const float* r_d, const ValidI& valid_i, const ValidD& valid_d,
                         std::size_t n, const WeightOptions& options, float* w_i, float* w_d,
                         const JointScale& initial) {
  // Residuals of the terms valid in both objectives, contiguous.
  std::vector<float> u, v;
  u.reserve(n);
  v.reserve(n);
  double sum_ii = 0.0, sum_dd = 0.0;
  std::size_t count_i = 0, count_d = 0;
  for (std::size_t k = 0; k < n; ++k) {
    if (valid_i(k)) sum_ii += double(r_i[k]) * r_i[k], ++count_i;
    if (valid_d(k)) sum_dd += double(r_d[k]) * r_d[k], ++count_d;
    if (valid_i(k) && valid_d(k)) {
      u.push_back(r_i[k]);
      v.push_back(r_d[k]);
    }
  }
  const double nu = options.nu;
  JointScale s;
  if (initial.valid()) {
    s = initial;
  } else {
    s.s_ii = count_i ? sum_ii / count_i : 0.0;
    s.s_dd = count_d ? sum_dd / count_d : 0.0;
  }
  if (u.size() >= 3 && s.valid()) {
    for (int it = 0; it < options.max_scale_iterations; ++it) {
      const JointScale next = weighted_moments(u, v, nu, s);
      if (!next.valid() || !std::isfinite(next.s_ii + next.s_dd + next.s_id)) break;
      const double change = std::abs(next.s_ii - s.s_ii) / s.s_ii + std::abs(next.s_dd - s.s_dd) / s.s_dd +
                            std::abs(next.s_id - s.s_id) / std::sqrt(s.s_ii * s.s_dd);
      s = next;
      if (change <= options.scale_tolerance) break;
    }
  }
  if (!s.valid()) {
    // Degenerate (no residual, or all zero in one objective): unit weights, as compute_weights.
    for (std::size_t k = 0; k < n; ++k) {
      w_i[k] = valid_i(k) ? 1.0f : 0.0f;
      w_d[k] = valid_d(k) ? 1.0f : 0.0f;
    }
    return s;
  }
  const double det = s.s_ii * s.s_dd - s.s_id * s.s_id;
  const float a = static_cast<float>(s.s_dd / det), b = static_cast<float>(-s.s_id / det),
              c = static_cast<float>(s.s_ii / det);
  const float inv_ii = static_cast<float>(1.0 / s.s_ii), inv_dd = static_cast<float>(1.0 / s.s_dd);
  const float fnu = static_cast<float>(nu), fnu1 = static_cast<float>(nu + 1.0), fnu2 = static_cast<float>(nu + 2.0);
  for (std::size_t k = 0; k < n; ++k) {
    const float x = r_i[k], y = r_d[k];
    if (valid_i(k) && valid_d(k)) {
      const float w = fnu2 / (fnu + a * x * x + 2.0f * b * x * y + c * y * y);
      w_i[k] = w;
      w_d[k] = w;
    } else {
      w_i[k] = valid_i(k) ? fnu1 / (fnu + x * x * inv_ii) : 0.0f;
      w_d[k] = valid_d(k) ? fnu1 / (fnu + y * y * inv_dd) : 0.0f;
    }
  }
  return s;
}

}  // namespace

JointScale compute_joint_weights(const float* r_i, const float* r_d, const unsigned char* valid_i,
                                 const unsigned char* valid_d, std::size_t n, const WeightOptions& options,
                                 float* w_i, float* w_d, const JointScale& initial) {
  return joint_weights(
      r_i, r_d, [valid_i](std::size_t k) { return valid_i[k] != 0; },
      [valid_d](std::size_t k) { return valid_d[k] != 0; }, n, options, w_i, w_d, initial);
}

JointScale compute_joint_weights_flagged(const float* r_i, const float* r_d, const std::uint8_t* flags,
                                         std::size_t n, const WeightOptions& options, float* w_i, float* w_d,
                                         const JointScale& initial) {
  return joint_weights(
      r_i, r_d, [flags](std::size_t k) { return (flags[k] & 1) != 0; },
      [flags](std::size_t k) { return (flags[k] & 2) != 0; }, n, options, w_i, w_d, initial);
}

}  // namespace bivo::odometry
