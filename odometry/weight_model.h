#pragma once
// The weight model of the robust objectives (paper eqs. `quadratic form`, `depth quadratic`):
// plain data that robust_weights.h and joint_weights.h estimate and the per-pixel kernels
// apply. The one header of the science that odometry/kernels/ reads.

namespace bivo::odometry {

// A weight model: how each term's weight follows from its residuals. Per-objective diagonal
// weights, or one weight per pixel from both residuals (the bivariate t of `joint`). The
// kernels apply it term by term (lane_weights in odometry/kernels/rgbd_kernels_impl.h).
struct ObjectiveWeights {
  // t-distribution: w = numerator / (denominator + r^2 inv_scale2), i.e. (nu + 1) / (nu + r^2 / sigma^2);
  // unit weights are 1 / (1 + 0 r^2).
  float numerator = 1.0f, denominator = 1.0f, inv_scale2 = 0.0f;
  float huber = 3.0e38f;  // Huber: w = min(1, k sigma / |r|) with huber = k sigma (huge: unit weights)
};
// The bivariate t of method joint: P = S^-1 (joint_weights.h), nu degrees of freedom.
struct JointScaleParams {
  float p_ii = 0, p_id = 0, p_dd = 0, nu = 5;
};
struct WeightModel {
  // kStored reuses the weights in the buffers (LinearizeOptions::update_weights = false);
  // every other kind writes them. Invalid terms always get weight 0. kJoint: one weight
  // (nu + 2) / (nu + r^T P r) for a term valid in both objectives (`joint`), the
  // t-distribution of `intensity` / `depth` (the marginals) for a term valid in one.
  enum Kind { kTDistribution, kHuber, kUnit, kStored, kJoint } kind = kUnit;
  ObjectiveWeights intensity, depth;
  JointScaleParams joint;
};

}  // namespace bivo::odometry
