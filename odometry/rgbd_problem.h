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
// linearize() accumulates a, b, H pixel by pixel (no n x 6 storage) and re-estimates the
// robust weights (robust_weights.h) from the residuals at x; full J / r / w on request.
// The reference and current levels must outlive the problem.
#include <array>
#include <string>
#include <vector>

#include "odometry/joint_weights.h"
#include "odometry/robust_weights.h"
#include "odometry/rgbd_pyramid.h"
#include "solvers/manifold.h"
#include "solvers/problem.h"

namespace bivo::odometry {

struct RgbdProblemOptions {
  WeightOptions weights;
  double min_depth = 0.1;          // metres: reference depths outside [min, max] are not used
  double max_depth = 10.0;
  double occlusion_margin = 0.1;   // metres: q_z beyond D_2(y) + margin counts as occluded
  // false: F_1 = F_I, F_2 = F_D (the paper's order). true: F_1 = F_D, F_2 = F_I, so the
  // weighted sum with lambda = 0 minimizes the depth objective alone (method "depth").
  bool depth_first = false;
  // true: ONE weight per pixel for (r_I, r_D) from the bivariate t-distribution with scale
  // matrix S (joint_weights.h; method "joint") instead of two independent weightings.
  bool joint_weights = false;
};

// What the latest linearize() saw (weights and scale are those of that call).
struct RgbdLinearizationStats {
  int terms = 0;               // reference pixels with valid depth (rows of r_I, r_D)
  int valid_intensity = 0;     // terms with a valid r_I at x
  int valid_depth = 0;         // terms with a valid r_D at x
  double sigma_intensity = 0.0, sigma_depth = 0.0;          // robust scales
  double weight_sum_intensity = 0.0, weight_sum_depth = 0.0;  // trace of Omega_I, Omega_D
  double f_intensity = 0.0, f_depth = 0.0;                  // F_I, F_D at x
  JointScale joint_scale;      // options.joint_weights: the scale matrix S (else zero)
};

class RgbdOdometryProblem final : public solvers::BiObjectiveProblem {
 public:
  RgbdOdometryProblem(const RgbdLevel& reference, const RgbdLevel& current, RgbdProblemOptions options = {});

  std::string name() const override;
  const solvers::Manifold& manifold() const override { return manifold_; }
  solvers::Linearization linearize(const Eigen::VectorXd& x, const solvers::LinearizeOptions& options) override;
  std::array<double, 2> evaluate(const Eigen::VectorXd& x) override;
  solvers::ResidualData residuals(int j, const Eigen::VectorXd& x, bool with_jacobian) override;

  int num_terms() const { return static_cast<int>(px_.size()); }
  const RgbdLinearizationStats& last_stats() const { return stats_; }
  const RgbdProblemOptions& options() const { return options_; }
  const RgbdLevel& reference() const { return *reference_; }
  const RgbdLevel& current() const { return *current_; }
  // F_I and F_D (in the paper's order, whatever depth_first says) at x with the latest
  // weights; weights are estimated at x first when linearize() was never called.
  std::array<double, 2> evaluate_intensity_depth(const Eigen::VectorXd& x);

 private:
  enum : unsigned char { kValidI = 1, kValidD = 2 };
  // Warps every term with T_21 = x: fills r_i_, r_d_, flags_, the warped points and the
  // interpolation gradients used by the Jacobians (a no-op when x is the cached x).
  void warp_all(const Eigen::VectorXd& x);
  void ensure_weights(const Eigen::VectorXd& x);
  // The weight stage: Omega_I, Omega_D from the residuals of the latest warp (warm-started
  // from the previous scales when warm_start).
  void estimate_weights(bool warm_start);
  void check_x(const Eigen::VectorXd& x) const;

  const RgbdLevel* reference_;
  const RgbdLevel* current_;
  RgbdProblemOptions options_;
  solvers::Se3Manifold manifold_;

  // Reference terms (structure of arrays): back-projected point and intensity.
  std::vector<float> px_, py_, pz_, i1_;
  // Per-term state at the latest warp.
  std::vector<float> r_i_, r_d_;
  std::vector<unsigned char> flags_, valid_i_, valid_d_;
  std::vector<float> qx_, qy_, qz_;          // warped points (cached for Jacobians)
  std::vector<float> gi_u_, gi_v_, gd_u_, gd_v_;  // dI_2/du * fx etc. at y_i
  // Weights of the latest linearize().
  std::vector<float> w_i_, w_d_;
  bool have_weights_ = false;
  // x of the latest warp_all(x): the outer loop evaluates x_new and then linearizes
  // at the same x_new, which then reuses the warp instead of repeating it.
  Eigen::VectorXd cached_x_;
  RgbdLinearizationStats stats_;
};

}  // namespace bivo::odometry
