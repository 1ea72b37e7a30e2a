#include "odometry/joint_weights.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "odometry/kernels/kernels.h"

namespace bivo::odometry {

double JointScale::correlation() const { return valid() ? s_id / std::sqrt(s_ii * s_dd) : 0.0; }

double JointScale::implied_lambda() const { return valid() ? s_ii / s_dd : 0.0; }

namespace {

using Vector3 = Eigen::Vector3d;
using Matrix3 = Eigen::Matrix3d;

Vector3 as_vector(const JointScale& s) { return {s.s_ii, s.s_id, s.s_dd}; }
JointScale as_scale(const Vector3& v, int passes) { return {v(0), v(1), v(2), passes}; }

// The fixed point S = M(S) = mean(w r r^T) solved by Newton's method on G(s) = M(s) - s,
// s = (S_II, S_ID, S_DD). The pass that gives M also gives dM/dP (P = S^-1, JointScaleSums),
// and dP = -P dS P, so each Newton step costs one pass, as a plain step S <- M(S) does.
// Newton needs ~2-4 passes per linearization where the plain iteration took up to 50 (it
// contracts slowly when the weights vary a lot). The plain step is taken instead when the
// Newton step is not finite, not positive definite, or leaves [min(s, M) / 2, 2 max(s, M)]
// on the diagonal. Stops when a step changes s by <= scale_tolerance (relative).
class JointScaleIteration {
 public:
  JointScaleIteration(const JointScale& start, double nu) : s_(start), nu_(nu) {}
  const JointScale& scale() const { return s_; }
  JointScaleParams params() const {
    const double det = s_.s_ii * s_.s_dd - s_.s_id * s_.s_id;
    return {static_cast<float>(s_.s_dd / det), static_cast<float>(-s_.s_id / det), static_cast<float>(s_.s_ii / det),
            static_cast<float>(nu_)};
  }
  // One pass's sums; false when the iteration has ended (converged, or no valid step).
  bool update(const JointScaleSums& t) {
    const double inv_n = 1.0 / static_cast<double>(t.count);
    const JointScale plain{t.m_ii * inv_n, t.m_id * inv_n, t.m_dd * inv_n, s_.passes + 1};
    if (!plain.valid() || !std::isfinite(plain.s_ii + plain.s_dd + plain.s_id)) return false;
    JointScale next = plain;
    const JointScale newton = newton_step(t, plain);
    if (newton.valid() && within_bounds(newton, plain)) next = newton;
    const double change = std::abs(next.s_ii - s_.s_ii) / s_.s_ii + std::abs(next.s_dd - s_.s_dd) / s_.s_dd +
                          std::abs(next.s_id - s_.s_id) / std::sqrt(s_.s_ii * s_.s_dd);
    s_ = next;
    return !(change <= tolerance);
  }
  double tolerance = 1e-4;

 private:
  JointScale newton_step(const JointScaleSums& t, const JointScale& plain) const {
    const double det = s_.s_ii * s_.s_dd - s_.s_id * s_.s_id;
    const double a = s_.s_dd / det, b = -s_.s_id / det, c = s_.s_ii / det;
    const double k = -1.0 / ((nu_ + 2.0) * static_cast<double>(t.count));  // dw/dq = -w^2 / (nu + 2)
    Matrix3 dm_dp;  // rows M_II, M_ID, M_DD; columns P_II, P_ID, P_DD (q = P_II x^2 + 2 P_ID x y + P_DD y^2)
    dm_dp << t.t40, 2.0 * t.t31, t.t22, t.t31, 2.0 * t.t22, t.t13, t.t22, 2.0 * t.t13, t.t04;
    dm_dp *= k;
    Matrix3 dp_ds;  // -P E P for E = dS/dS_II, dS/dS_ID (symmetric), dS/dS_DD
    dp_ds << -a * a, -2.0 * a * b, -b * b, -a * b, -(a * c + b * b), -b * c, -b * b, -2.0 * b * c, -c * c;
    const Matrix3 jacobian = dm_dp * dp_ds - Matrix3::Identity();
    const Vector3 residual = as_vector(plain) - as_vector(s_);
    const Vector3 step = jacobian.fullPivLu().solve(residual);
    if (!step.allFinite()) return {};
    return as_scale(as_vector(s_) - step, plain.passes);
  }
  bool within_bounds(const JointScale& n, const JointScale& plain) const {
    const auto inside = [](double v, double x, double y) {
      return v >= 0.5 * std::min(x, y) && v <= 2.0 * std::max(x, y);
    };
    return inside(n.s_ii, s_.s_ii, plain.s_ii) && inside(n.s_dd, s_.s_dd, plain.s_dd);
  }

  JointScale s_;
  double nu_;
};

}  // namespace

JointScale estimate_joint_scale(const TermBuffers& buf, std::size_t n, const WeightOptions& options,
                                const JointScale& initial, const KernelTable& kernels, int threads) {
  JointScale s = initial;
  s.passes = 0;
  if (!initial.valid()) {
    // From the marginal second moments (s_id = 0).
    double sum_ii = 0.0, sum_dd = 0.0;
    std::size_t count_i = 0, count_d = 0;
    for (std::size_t k = 0; k < n; ++k) {
      if (buf.flags[k] & 1) sum_ii += double(buf.r_i[k]) * buf.r_i[k], ++count_i;
      if (buf.flags[k] & 2) sum_dd += double(buf.r_d[k]) * buf.r_d[k], ++count_d;
    }
    s = JointScale{count_i ? sum_ii / count_i : 0.0, 0.0, count_d ? sum_dd / count_d : 0.0, 0};
  }
  if (!s.valid()) return s;
  JointScaleIteration it(s, options.nu);
  it.tolerance = options.scale_tolerance;
  const std::size_t padded = padded_terms(n);
  for (int pass = 0; pass < options.max_scale_iterations; ++pass) {
    const JointScaleParams p = it.params();
    const JointScaleSums sums = sum_over_chunks<JointScaleSums>(
        padded, kChunkTerms, threads,
        [&](std::size_t b, std::size_t e) { return kernels.joint_scale_sums(p, buf, b, e); });
    if (sums.count < 3 || !it.update(sums)) break;
  }
  return it.scale();
}

WeightModel joint_weight_model(const JointScale& s, const WeightOptions& options) {
  WeightModel m;
  if (!s.valid()) return m;  // unit weights on the valid terms, as compute_weights
  const double det = s.s_ii * s.s_dd - s.s_id * s.s_id;
  m.kind = WeightModel::kJoint;
  m.joint = {static_cast<float>(s.s_dd / det), static_cast<float>(-s.s_id / det), static_cast<float>(s.s_ii / det),
             static_cast<float>(options.nu)};
  for (auto [marginal, scale2] : {std::pair{&m.intensity, s.s_ii}, std::pair{&m.depth, s.s_dd}}) {
    marginal->numerator = static_cast<float>(options.nu + 1.0);
    marginal->denominator = static_cast<float>(options.nu);
    marginal->inv_scale2 = static_cast<float>(1.0 / scale2);
  }
  // A scale too small for the kernels' float arithmetic (residuals that vanish: depth that fits
  // to the last bit) has no float inverse: unit weights, as without a scale.
  for (const float v : {m.joint.p_ii, m.joint.p_id, m.joint.p_dd, m.intensity.inv_scale2, m.depth.inv_scale2}) {
    if (!std::isfinite(v)) return WeightModel{};
  }
  return m;
}

JointScale compute_joint_weights(const float* r_i, const float* r_d, const unsigned char* valid_i,
                                 const unsigned char* valid_d, std::size_t n, const WeightOptions& options, float* w_i,
                                 float* w_d, const JointScale& initial) {
  // The kernels' layout: padded buffers, residuals 0 where invalid, validity as flags.
  const std::size_t padded = padded_terms(n);
  std::vector<float> ri(padded, 0.0f), rd(padded, 0.0f), wi(padded, 0.0f), wd(padded, 0.0f);
  std::vector<std::uint8_t> flags(padded, 0);
  for (std::size_t k = 0; k < n; ++k) {
    flags[k] = static_cast<std::uint8_t>((valid_i[k] ? 1 : 0) | (valid_d[k] ? 2 : 0));
    ri[k] = valid_i[k] ? r_i[k] : 0.0f;
    rd[k] = valid_d[k] ? r_d[k] : 0.0f;
  }
  TermBuffers buf;
  buf.r_i = ri.data();
  buf.r_d = rd.data();
  buf.flags = flags.data();
  buf.w_i = wi.data();
  buf.w_d = wd.data();
  const KernelTable& kernels = default_kernels();
  const JointScale s = estimate_joint_scale(buf, n, options, initial, kernels, 1);
  kernels.weigh(joint_weight_model(s, options), ObjectiveMask{true, true}, buf, 0, padded);
  std::copy(wi.begin(), wi.begin() + static_cast<std::ptrdiff_t>(n), w_i);
  std::copy(wd.begin(), wd.begin() + static_cast<std::ptrdiff_t>(n), w_d);
  return s;
}

}  // namespace bivo::odometry
