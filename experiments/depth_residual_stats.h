#pragma once
// Statistics of the depth residual at the true motion: how a sequence's depth images
// disagree with each other when moved by the ground truth. Used to compare real sensors with
// renderings (`bivo depth-stats`, docs/synthetic.md "Sensor defects").
//
// For frame pairs (i, i + gap) every pixel of frame i with depth z is lifted (K^-1, after
// the sequence's undistortion), moved by the ground-truth T_ji at the colour timestamps (as
// a tracker is judged), projected into frame j, and compared with frame j's depth there
// (bilinear where the 4 neighbours agree within 5 %, else nearest): r = z_j - z'. Pixels
// with |r| > 10 % of z' (occlusions, missing surfaces) are counted as outliers and left out.
//
// The colour images are compared at the same correspondences (every 4th pixel and row, inliers
// whose colour is flat, |dI/du| + |dI/dv| < 4 gray levels per pixel, and neither dark nor
// saturated): y = ln I_j(x') - ln I_i(x) is fit by ln(1 - k rho'^2) - ln(1 - k rho^2) plus one
// offset per pair (exposure), Huber-weighted. k is a radial fall-off fixed to the camera
// (vignetting, the renderer's model; rho^2 as in edge/centre); the scene's own shading moves
// with the scene and does not fit it.
//
//   DepthResidualOptions o;  o.gap = 1;  o.max_pairs = 40;
//   DepthResidualStats s = depth_residual_stats("/data/rgbd_dataset_freiburg1_rpy", o);
#include <string>
#include <vector>

namespace bivo::experiments {

struct DepthResidualOptions {
  int gap = 1;          // frames between the two images of a pair
  int max_pairs = 40;   // pairs spread evenly over the sequence
  int max_frames = -1;  // only the first N frames (-1: all)
};

struct DepthResidualStats {
  std::string sequence;
  int pairs = 0;
  double median_depth_m = 0, beyond_3m = 0;  // of the compared pixels
  double outlier_share = 0;                  // |r| > 10 % z
  double mean_rel = 0;                       // mean r / z of the inliers
  double spread_z2 = 0;                      // 1.4826 MAD of r / z^2 [1/m]
  double correlation_px = 0;                 // lag where the residual's autocorrelation falls to 1/e
  double radial_ratio = 0;                   // RMS(r/z) at rho^2 > 0.5 over RMS(r/z) at rho^2 < 0.1
  double depth_exponent = 0;                 // p of spread(r) ~ z^p over depth bins
  double pair_bias_rms = 0;                  // RMS over pairs of each pair's mean r / z
  double colour_falloff = 0;                 // k above; NaN when the motion does not observe it
};

// Throws bivo::Error when gap or max_pairs is below 1, or the sequence has no ground truth or
// fewer than gap + 1 frames.
DepthResidualStats depth_residual_stats(const std::string& sequence_dir, const DepthResidualOptions& options);

// Markdown table, one row per sequence.
std::string depth_residual_table(const std::vector<DepthResidualStats>& rows);

}  // namespace bivo::experiments
