#pragma once
// The RGB-D odometry problem of ONE frame pair at ONE pyramid level, as a
// solvers::BiObjectiveProblem over x = T_21 (Se3Manifold ambient 7-vector):
//   F_I = r_I^T Omega_I r_I,  F_D = r_D^T Omega_D r_D  (eqs. `quadratic form`, `depth quadratic`)
// with, for every reference pixel x_i of frame 1 with valid depth z_i
// (eq. `new definition of residual`):
//   p_i   = z_i K^-1 [x_i; 1],   q_i = T_21 p_i,   y_i = tau = pi(K q_i)
//   r_I^i = I_2(y_i) - I_1(x_i),   r_D^i = D_2(y_i) - [q_i]_z
// I_2, D_2 bilinearly interpolated. A term is invalid (r = 0, J = 0, weight 0) when y_i
// leaves the image, q_i lies behind the camera, or it is occluded (q_z > D_2(y_i) + margin);
// r_D additionally needs the four depth neighbours of y_i. Jacobians are exact derivatives
// of these residuals for the left perturbation x (+) d = exp(d) T_21, d = [v; w]:
//   d q / d d = [I, -q^],  J = c^T [I, -q^] = [c, q x c]  with c = (dr/dy)(dy/dq) (- e_z for r_D).
//
// Two implementations of the same formulas: linearize() / evaluate() run the float SIMD
// kernels over structure-of-arrays buffers (rgbd_kernels.h; pose-independent data once per
// level, reference_terms.h), residuals() and the full data of want_full the double path
// (residual_definition.h) that the finite-difference tests check. The reference and current
// levels must outlive the problem.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "odometry/joint_weights.h"
#include "odometry/kernels/kernels.h"
#include "odometry/reference_terms.h"
#include "odometry/residual_definition.h"
#include "odometry/rgbd_pyramid.h"
#include "odometry/robust_weights.h"
#include "solvers/geometry/manifold.h"
#include "solvers/problem.h"

namespace bivo::odometry {

// Which image gradients the Jacobians use: "forward" (the current image at y_i, exact),
// "inverse" (the reference image at x_i, precomputed per level: inverse-compositional
// style), "esm" (their mean, Benhimane and Malis 2004). "auto" is the tracker's default:
// each method's own choice (method_jacobian() in odometry_methods.h); a problem must be
// given a resolved kind.
enum class JacobianKind { kForward, kInverse, kEsm, kMethodDefault };
JacobianKind parse_jacobian_kind(const std::string& name);  // unknown -> bivo::Error listing the valid ones
const char* to_string(JacobianKind kind);

struct RgbdProblemOptions {
  WeightOptions weights;
  double min_depth = 0.1;  // metres: reference depths outside [min, max] are not used
  double max_depth = 10.0;
  double occlusion_margin = 0.1;  // metres: q_z beyond D_2(y) + margin counts as occluded
  // r_D^i divided by (z_i / 1 m)^p, z_i the reference depth: F_D whitened for depth noise
  // that grows with depth (structured light and stereo: sigma_z ~ z^2 to z^3), so that far
  // pixels, several times noisier, do not count as much as near ones. 0: r_D as defined. -1
  // ("auto", the tracker's default) names the method's own (method_depth_noise_exponent()).
  int depth_noise_exponent = 0;
  // 1: r_I = I_2(y) - (a I_1(x) + b), the affine brightness (a, b) refit by weighted least
  // squares on r_I at every weight stage that weighs r_I and r_D together (auto-exposure and
  // gain steps are a brightness change, not photometric noise: without it the t-scale of r_I
  // absorbs them). Not on F_I alone, which cannot tell a brightness change from motion where
  // the image is smooth (a shifted ramp is an offset); r_D fixes the motion. 0: r_I as defined.
  // 2: also a camera-fixed radial fall-off, r_I = I_2(y) - ((a + c (rho_y^2 - rho_x^2)) I_1(x)
  // + b), rho the normalized distance to the principal point (affine_brightness.h): vignetting
  // moves with the camera, so without c it pulls F_I toward no motion where texture is weak.
  // -1 ("auto", the tracker's default) names the method's own (method_affine_brightness()).
  int affine_brightness = 0;
  // With affine_brightness 2: the fit of c also minimizes radial_prior (sum of the weights) c^2,
  // a ridge toward no fall-off, so that c stays near 0 unless the pair's motion shows it
  // (q^2 well above radial_prior on average); in gray levels^2. 0: c as the data alone fit it.
  // 0.3: chosen held out for joint (docs/results/defaults.md).
  double radial_prior = 0.3;
  // false: F_1 = F_I, F_2 = F_D (the paper's order). true: F_1 = F_D, F_2 = F_I, so the
  // weighted sum with lambda = 0 minimizes the depth objective alone (method "depth").
  bool depth_first = false;
  // true: ONE weight per pixel for (r_I, r_D) from the bivariate t-distribution with scale
  // matrix S (joint_weights.h; method "joint") instead of two independent weightings.
  bool joint_weights = false;
  // false: linearize() and evaluate() build F_1 only and report F_2 = 0 with a zero model
  // (methods with lambda = 0); objectives_at() still gives both.
  bool model_f2 = true;
  JacobianKind jacobian = JacobianKind::kForward;
  int threads = 1;  // per-pixel passes; results are identical for every count
  // degenerate(x): a pose whose warp leaves fewer valid terms of F_1 than this, or fewer than
  // this fraction of the reference terms, measures too little to be an estimate (a long step
  // can reach F = 0 by leaving the image). The tracker sets the count from min_valid_pixels.
  // Consecutive frames keep most terms (fr1/rpy at 320x240: 94-100 % at the estimated poses
  // of exact, 83-99 % at the identity); ipopt-nlp's wrong poses there kept 22 % and 45 %.
  int min_valid_terms = 1;
  double min_valid_fraction = 0.5;
};

// Throws bivo::Error naming the first option of o out of its range ("auto" values included:
// the tracker resolves them first).
void check_problem_options(const RgbdProblemOptions& o);

// What the latest linearize() saw (weights and scale are those of that call).
struct RgbdLinearizationStats {
  int terms = 0;                                              // reference pixels with valid depth (rows of r_I, r_D)
  int valid_intensity = 0;                                    // terms with a valid r_I at x
  int valid_depth = 0;                                        // terms with a valid r_D at x
  double sigma_intensity = 0.0, sigma_depth = 0.0;            // robust scales
  double weight_sum_intensity = 0.0, weight_sum_depth = 0.0;  // trace of Omega_I, Omega_D
  JointScale joint_scale;                                     // options.joint_weights: the scale matrix S (else zero)
  double f_intensity = 0.0, f_depth = 0.0;                    // F_I, F_D at x (0 when not modelled)
  double brightness_gain = 1.0, brightness_offset = 0.0;      // (a, b) of affine_brightness
  double brightness_radial = 0.0;                             // c of affine_brightness 2
};

class RgbdOdometryProblem final : public solvers::BiObjectiveProblem {
 public:
  RgbdOdometryProblem(const RgbdLevel& reference, const RgbdLevel& current, RgbdProblemOptions options = {});

  std::string name() const override;
  const solvers::Manifold& manifold() const override { return manifold_; }
  solvers::Linearization linearize(const Eigen::VectorXd& x, const solvers::LinearizeOptions& options) override;
  std::array<double, 2> evaluate(const Eigen::VectorXd& x) override;
  // The same F in one warp that writes nothing: the buffers keep the previous warp.
  std::array<double, 2> evaluate_only(const Eigen::VectorXd& x) override;
  solvers::ResidualData residuals(int j, const Eigen::VectorXd& x, bool with_jacobian) override;
  // Too few valid terms of F_1 at x (RgbdProblemOptions::min_valid_terms, min_valid_fraction).
  std::optional<std::string> degenerate(const Eigen::VectorXd& x) override;

  int num_terms() const { return static_cast<int>(reference_terms_.count); }
  const RgbdLinearizationStats& last_stats() const { return stats_; }
  const RgbdProblemOptions& options() const { return options_; }
  const RgbdLevel& reference() const { return *reference_; }
  const RgbdLevel& current() const { return *current_; }
  // F_I and F_D (in the paper's order, whatever depth_first says) at x with the latest
  // weights; weights are estimated at x first when linearize() was never called.
  std::array<double, 2> evaluate_intensity_depth(const Eigen::VectorXd& x);
  // F_I and F_D at x with both objectives' weights estimated at x, whatever model_f2 says
  // (what a one-objective method reports for the objective it did not optimize). The
  // problem's state is left at x with these weights. `profile` may be null.
  std::array<double, 2> objectives_at(const Eigen::VectorXd& x, solvers::PhaseProfile* profile = nullptr);
  // RMS motion in pixels of the reference points' projections that the tangent step delta
  // causes at x (first order; a fixed sample of at most 4096 terms, metric taken at the
  // first x asked): what the tracker's stopping rule compares with a fraction of a pixel.
  double pixel_motion(const Eigen::VectorXd& x, const Eigen::VectorXd& delta);
  // The instruction set of the float kernels (default: the best this CPU runs).
  KernelIsa kernel_isa() const { return kernels_->isa; }
  void set_kernel_isa(KernelIsa isa);
  // Switches the image gradients of later linearizations (the weights and scales estimated so
  // far are kept): the tracker's exact finish goes from inverse / esm to forward. Reference
  // gradients exist only when the problem was built with a non-forward kind; asking for them
  // otherwise throws bivo::Error.
  void set_jacobian(JacobianKind kind);
  // Switches the weighting (joint bivariate-t or one t per objective) and whether F_2 is
  // modelled, for later linearizations; every weight is re-estimated at the next one (the
  // scales are kept as warm starts). Method robust leaves joint's weighted sum for the
  // photometric objective alone when the depth fails its trust test.
  void set_objectives(bool joint_weights, bool model_f2);

 private:
  ObjectiveMask modelled() const;
  // Warps every term with T_21 = x (objectives `mask`): residuals, gradients, flags; with
  // weighted_sums also F_j under the stored weights. A no-op when x and mask are cached.
  void warp_all(const Eigen::VectorXd& x, ObjectiveMask mask, bool weighted_sums);
  // Scales of the objectives in `mask` from the residuals in the buffers -> model_.
  void estimate_weights(ObjectiveMask mask, WarpSums& at);
  // affine_brightness: (a, b) (and c) refit to the stored r_I, the stored r_I (and at.ss_i) corrected.
  void refit_brightness(WarpSums& at);
  DoublePathOptions double_path_options() const {
    return {options_.occlusion_margin,     gradients_,
            options_.depth_noise_exponent, stats_.brightness_gain,
            stats_.brightness_offset,      stats_.brightness_radial};
  }
  // Weights of the objectives in `mask` estimated at x unless some already exist.
  void ensure_weights(const Eigen::VectorXd& x, ObjectiveMask mask);
  void check_x(const Eigen::VectorXd& x) const;
  TermBuffers buffers();
  WarpParams warp_params(const Eigen::VectorXd& x, ObjectiveMask mask) const;

  const RgbdLevel* reference_;
  const RgbdLevel* current_;
  RgbdProblemOptions options_;
  solvers::Se3Manifold manifold_;
  const KernelTable* kernels_;
  GradientSource gradients_;

  ReferenceTerms reference_terms_;
  std::vector<float> own_cells_;  // the current level interleaved, when the level has none
  const float* cells_ = nullptr;
  // Per-term state at the latest warp (padded_terms(count) entries each).
  // Pooled (pooled_floats.h): not initialized beyond the zeroed padding; every pass writes
  // an entry before any pass reads it.
  PooledFloats r_i_, r_d_, gi_u_, gi_v_, gd_u_, gd_v_, w_i_, w_d_;
  PooledFloats q_, rho2_;  // affine_brightness 2: the radial regressor per term, rho_x^2 per reference term
  // The validity flags, one byte per term, four to a float of a pooled block (a vector of
  // bytes was faulted in and zeroed afresh for every pair); the warp writes every entry.
  PooledFloats flag_storage_;
  std::uint8_t* flags() { return reinterpret_cast<std::uint8_t*>(flag_storage_.data()); }
  ObjectiveMask weights_mask_{false, false};  // objectives whose weights the buffers hold
  WeightModel model_;                         // as of the latest estimate_weights()
  // The latest warp: at which x, for which objectives, and its sums.
  Eigen::VectorXd warp_x_;
  ObjectiveMask warp_mask_{false, false};
  WarpSums warp_sums_;
  // The sums of the latest evaluate_only() pass and its x (degenerate() reads the valid
  // counts there instead of warping the solve's last point again).
  Eigen::VectorXd counted_x_;
  WarpSums counted_sums_;
  bool warp_sums_weighted_ = false;  // warp_sums_.f_* are F under the current weights
  // F under the current weights at warp_x_ as of the latest linearize() there.
  std::optional<std::array<double, 2>> f_at_warp_;
  // The latest linearize() (without full data) while its x and weights are current: a
  // solve that starts where the previous one ended (warm-started Pareto points) gets it back
  // instead of re-estimating the same weights from the same residuals.
  std::optional<solvers::Linearization> last_linearization_;
  // pixel_motion(): mean of J_y^T J_y over the sample, J_y = d y / d delta (2 x 6).
  std::optional<Eigen::Matrix<double, 6, 6>> motion_metric_;
  RgbdLinearizationStats stats_;
};

}  // namespace bivo::odometry
