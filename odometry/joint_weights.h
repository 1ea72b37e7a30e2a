#pragma once
// Joint robust weights of the 2-vector r_k = (r_I,k, r_D,k) (Kerl, Sturm, Cremers, IROS 2013,
// "Dense visual SLAM for RGB-D cameras"): r_k follows a bivariate t-distribution with nu
// degrees of freedom (nu = 5) and 2x2 scale matrix S, so every pixel has ONE weight
//   w_k = (nu + 2) / (nu + r_k^T S^-1 r_k)
// and S solves the weighted fixed point S = 1/n sum_k w_k r_k r_k^T (by Newton's method from
// the previous linearization's S, one kernel pass per step, tolerance
// WeightOptions::scale_tolerance on S's relative change; joint_weights.cpp). Terms with only
// one valid residual use the marginal of that distribution, a univariate t with scale S_jj:
// w = (nu + 1) / (nu + r^2 / S_jj).
//
// The cost sum_k w_k r_k^T S^-1 r_k equals, without its cross term 2 (S^-1)_ID w r_I r_D,
// (S^-1)_II (F_I + lambda F_D) with Omega_I = Omega_D = diag(w) and the implied
//   lambda = (S^-1)_DD / (S^-1)_II = S_II / S_DD,
// a weighted sum of the paper's two objectives (docs/odometry.md, "joint": the cross term
// is dropped; its size, the correlation rho = S_ID / sqrt(S_II S_DD), is reported).
#include <cstddef>
#include <cstdint>

#include "odometry/kernels/kernels.h"
#include "odometry/robust_weights.h"

namespace bivo::odometry {

struct JointScale {
  double s_ii = 0.0, s_id = 0.0, s_dd = 0.0;  // [gray^2], [gray m], [m^2]
  int passes = 0;                             // passes over the terms that found S
  bool valid() const { return s_ii > 0.0 && s_dd > 0.0 && determinant() > 0.0; }
  double correlation() const;     // S_ID / sqrt(S_II S_DD); 0 when !valid()
  double implied_lambda() const;  // S_II / S_DD [gray^2 / m^2]; 0 when !valid()
  // det S, the generalized variance of (r_I, r_D).
  double determinant() const { return s_ii * s_dd - s_id * s_id; }
};

// Fills w_i and w_d (equal where both residuals are valid, 0 where a residual is invalid)
// and returns S. `initial` (when valid) starts the fixed point there. When fewer than 3
// terms have both residuals the scale is that of the marginals alone (s_id = 0).
JointScale compute_joint_weights(const float* r_i, const float* r_d, const unsigned char* valid_i,
                                 const unsigned char* valid_d, std::size_t n, const WeightOptions& options, float* w_i,
                                 float* w_d, const JointScale& initial = {});
// Over the RGB-D problem's term buffers (n terms, padded_terms(n) entries; flags bit 0 =
// r_I valid, bit 1 = r_D valid): S alone, each pass by `kernels` over `threads` (results do
// not depend on the thread count). The weights are then applied by the kernels' weight
// stage with joint_weight_model(S), fused into the normal equations.
JointScale estimate_joint_scale(const TermBuffers& buf, std::size_t n, const WeightOptions& options,
                                const JointScale& initial, const KernelTable& kernels, int threads);
// WeightModel::kJoint for S (unit weights when S is not valid or has no float inverse).
WeightModel joint_weight_model(const JointScale& s, const WeightOptions& options);

}  // namespace bivo::odometry
