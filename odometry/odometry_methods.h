#pragma once
// The odometry methods and how each chooses its scalarization parameter (paper Sec. III):
//   single    F_I only                       weighted sum, lambda = 0
//   depth     F_D only                       weighted sum with F_1 = F_D, lambda = 0
//   fixed     F_I + lambda F_D               lambda given
//   tykkala   F_I + lambda F_D               lambda = |median(I) / median(D)|^2 (Tykkala et al. 2011)
//   weighted  F_I + lambda F_D               lambda = phi gamma^2 pi(D)^2 / pi(I)^2
//                                            (eqs. `eq to calculate lambda`, `scale factor`,
//                                            `image complexity metric`, `depth complexity metric`)
//   bounded   min F_I s.t. F_D <= eps_D      eps_D = eps_max if pi(D) <= delta else eps_min
//                                            (eq. `bounded objective form`)
// and, beyond the paper (docs/odometry.md, "Data-driven policies"):
//   joint     F_I + lambda F_D with ONE bivariate-t weight per pixel (joint_weights.h, Kerl et
//             al. IROS 2013); lambda = S_II / S_DD, re-estimated at every linearization
//   scaled    F_I + lambda F_D               lambda = kappa sigma_I^2 / sigma_D^2 from the robust
//                                            scales of the current linearization
//   noise-bounded  per level: x_I = argmin F_I; then min F_I s.t. F_D <= eps_D with
//             eps_bar = eps_ratio * (F_D / trace Omega_D at x_I), the depth-residual level at the
//             photometric solution; guard: when F_I rises by more than guard * sigma_I^2 (its
//             noise variance: a chi-square-like test of the photometric data) they reject the
//             bound (biased depth) and it is relaxed (x_I kept).
//   robust    per level: joint's weighted sum with lambda = robust_kappa S_II / S_DD, then the
//             depth trust test (depth_trust.h) at its estimate; when the photometric data reject
//             it (T > trust), that level and every finer one are solved on F_I alone from there
//             (the default for an unknown sensor).
// Statistics are those of the reference frame at full resolution (image_statistics.h).
//
// eps_D is a bound on F_D = sum_i w_i r_D,i^2, which grows with the number of valid pixels
// and with the weights. The parameters are therefore given per unit weight, in m^2:
//   eps_D = eps_bar * sum_i w_D,i    (F_D <= eps_D  <=>  weighted mean r_D^2 <= eps_bar)
// evaluated with the weights of each linearization, so one eps_bar serves every pyramid
// level and image size.
#include <optional>
#include <string>
#include <vector>

#include "odometry/image_statistics.h"

namespace bivo::odometry {

enum class Method { kSingle, kDepth, kFixed, kTykkala, kWeighted, kBounded, kJoint, kScaled, kNoiseBounded, kRobust };

// Unknown name -> bivo::Error listing the valid ones.
Method parse_method(const std::string& name);
const char* to_string(Method method);
std::vector<std::string> method_names();
bool is_bounded(Method method);  // bounded, noise-bounded: epsilon-constraint steps
// joint, scaled: lambda is chosen per linearization from the residuals (residual_lambda()).
bool lambda_from_residuals(Method method);
// joint, robust: one bivariate-t weight per pixel (joint_weights.h).
bool uses_joint_weights(Method method);
// "gn" for the weighted-sum methods, "exact" for bounded.
std::string default_backend(Method method);

// Defaults chosen by the sweeps of docs/results/defaults.md.
struct PolicyParameters {
  double lambda = 1e3;        // method fixed [gray^2 / m^2]
  double phi = 100.0;         // method weighted: the adjustable constant of eq. `eq to calculate lambda`
  double delta = 0.02;        // method bounded: threshold on pi(D) [m per pixel]
  double eps_min = 3e-4;      // method bounded: per-unit-weight bound [m^2] on rich structure
  double eps_max = 1e-3;      // method bounded: per-unit-weight bound [m^2] on poor structure
  std::optional<double> eps;  // method bounded: fixed per-unit-weight bound overriding the rule
  // scaled, noise-bounded: chosen by leave-one-sequence-out over every sequence at hand
  // (docs/results/defaults.md, "Held out").
  double kappa = 0.05;     // method scaled: lambda = kappa sigma_I^2 / sigma_D^2
  double eps_ratio = 1.0;  // method noise-bounded: eps_bar / depth-residual level at x_I
  double guard = 42.0;     // method noise-bounded: rise of F_I / sigma_I^2 that relaxes the bound
  // method noise-bounded: a level whose bound the guard relaxed continues its photometric
  // solution x_I to this relative merit change (its coarser levels may have pulled its start
  // towards the depth objective); 1.055x -> 1.03x worst ratio to single (docs/odometry.md).
  double relaxed_tolerance = 1e-5;
  // method joint: the relative merit change that ends a level (TrackerOptions::
  // relative_decrease_tolerance ends the other methods' levels); joint re-estimates its 2x2
  // scale, hence its whole cost, at every linearization. -1 (the default): the method's own
  // (method_joint_tolerance(), chosen held out).
  double joint_tolerance = -1.0;
  // method robust: the threshold on the depth trust statistic T (depth_trust.h) above which a
  // level's bi-objective estimate is rejected for the photometric one; kTrustOff and above: the
  // test is off and T is not evaluated. T also grows with the photometric model's own errors
  // (exposure changes, blur, rolling shutter), so no threshold helped on every sequence at hand
  // (docs/results/robust.md).
  static constexpr double kTrustOff = 1e12;
  double trust = kTrustOff;
  // methods joint, robust: the coarsest N levels first solve F_I alone (own t-weights) and
  // start the bi-objective solve from its estimate (fr1/rpy pairs of 9-14 deg no longer fall
  // into the depth objective's basin at 80x60). -1 (auto): the method's own,
  // method_photometric_start_levels().
  int photometric_start_levels = -1;
  // methods joint and robust, at the photometric start levels: 1 also solves the level from
  // the prior (the coarser level's estimate) and, where the two estimates are different minima
  // (0.5 deg or 1 cm apart), keeps the one whose scale matrix S has the smaller determinant
  // (the generalized variance of (r_I, r_D): the bivariate t's likelihood with S at its fixed
  // point); where F_I alone follows exposure changes or blur rather than texture, its start
  // misleads. 0: the photometric start alone. 1 is chosen held out in every fold for both
  // methods (docs/results/defaults.md, "Held out").
  int both_starts = 1;
  // method robust: lambda = robust_kappa S_II / S_DD, joint's balance of the two residuals
  // scaled down: where the image has texture the depth objective counts less (a biased depth
  // image pulls the estimate less), where it has none S_II / S_DD is large and depth still
  // decides. Chosen by leave-one-sequence-out (docs/results/robust.md).
  double robust_kappa = 0.5;
  // method robust: the relative merit change that ends the finest level (joint_tolerance ends
  // the coarser ones). A speed setting, chosen held out under the CPU budget of 1.3x weighted
  // at 640x480 (`bivo loso --cost-budget 1.3`; docs/results/robust.md, "Cost"): 1e-5 costs
  // 1.46x there.
  double robust_finest_tolerance = 1e-3;
  // method robust: the step norm (m, rad) that ends the finest level (-1: the tracker's
  // step_tolerance, 1e-4). Its re-estimated weights make the finest level crawl towards the
  // fixed point, and stopping short leaves pair errors correlated along the motion. Chosen
  // held out over both resolutions within the CPU budget (docs/results/robust.md, "Cost").
  double robust_finest_step_tolerance = 2e-5;
};

// Method robust evaluates its depth trust test (PolicyParameters::trust below kTrustOff).
inline bool trust_test_on(const PolicyParameters& p) { return p.trust < PolicyParameters::kTrustOff; }

// Whether the method's per-frame rule reads the frame's medians (FrameStatistics::has_medians
// must then be set: add_medians()); only tykkala does.
bool reads_medians(Method method);
// The rule reads the reference frame's statistics (pi, variances: FrameStatistics): weighted
// and bounded. (tykkala reads only the medians, computed on demand.)
bool reads_frame_statistics(Method method);

// Throws bivo::Error when s has no medians (as frame_lambda() for tykkala).
double tykkala_lambda(const FrameStatistics& s);
// gamma = var(I) / var(D) (eq. `scale factor`); lambda = phi gamma^2 pi(D)^2 / pi(I)^2.
double adaptive_lambda(const FrameStatistics& s, double phi);
// eps_bar [m^2 per unit weight] of the bounded method.
double bounded_epsilon_per_weight(const FrameStatistics& s, const PolicyParameters& p);

// lambda of a weighted-sum method for a frame with statistics s (0 for single and depth), or
// nullopt when the frame's statistics leave it undefined (non-finite or negative, e.g. a
// frame without valid depth or without texture); `why` then names the values. Throws
// bivo::Error for bounded and noise-bounded; joint and scaled have no per-frame lambda:
// Error too (use residual_lambda()).
std::optional<double> frame_lambda(Method method, const FrameStatistics& s, const PolicyParameters& p,
                                   std::string* why = nullptr);
// The same, throwing bivo::Error with that message when lambda is undefined.
double method_lambda(Method method, const FrameStatistics& s, const PolicyParameters& p);

struct RgbdLinearizationStats;
enum class JacobianKind;  // rgbd_problem.h
// The Jacobian kind a method uses at a level when asked for "auto" (the tracker's default); any
// other request is returned unchanged. joint: inverse (reference-side gradients, as the IROS
// 2013 tracker it reproduces, dvo_core, precomputes them per level); robust: inverse at the
// coarser levels and forward (exact) at the finest, where precomputing reference-side gradients
// and then finishing with exact ones cost two solves at full resolution
// (docs/results/robust.md, "Cost"); every other method: forward. Chosen on all the data at hand
// (docs/odometry.md, "How the defaults were chosen").
JacobianKind method_jacobian(Method method, JacobianKind requested, bool finest_level = false);
// The depth noise exponent (RgbdProblemOptions::depth_noise_exponent) a method uses when asked
// for -1 ("auto", the tracker's default); any other request is returned unchanged. joint and
// robust: 3 (their robust scales assume one noise level for all pixels, which over-trusts far
// ones; the real fr3 residual's spread grows as z^3; chosen by leave-one-sequence-out,
// docs/results/robust.md); the others: 0 (the paper's r_D, the settings their defaults were
// chosen with).
int method_depth_noise_exponent(Method method, int requested);
// The affine brightness (RgbdProblemOptions::affine_brightness) a method uses when asked for -1
// ("auto", the tracker's default); any other request is returned unchanged. joint: 2, robust:
// 1 (their t-scale of r_I otherwise grows with every exposure change, and with it lambda =
// S_II / S_DD: depth is trusted the more the brighter the step; joint's also fits the camera's
// fall-off, which robust's CPU budget leaves out; chosen by leave-one-sequence-out,
// docs/results/defaults.md), joint 1 where the frames' fall-off is divided out
// (TrackerOptions::vignetting: a per-pair fall-off fit on a textureless plane reads the
// exposure gain as rotation); the others: 0 (r_I as the paper defines it).
int method_affine_brightness(Method method, int requested, bool falloff_divided_out = false);
// The photometric start (PolicyParameters::photometric_start_levels) a method uses when asked
// for -1 ("auto", the default); any other request is returned unchanged. joint: 3, robust
// (and the methods that ignore it): 1; each chosen by leave-one-sequence-out
// (docs/results/defaults.md, "Held out").
int method_photometric_start_levels(Method method, int requested);
// The level tolerance (PolicyParameters::joint_tolerance) a method uses when asked for -1
// ("auto", the default); any other request is returned unchanged. joint: 1e-3, robust: 1e-4
// (the methods that ignore it: 1e-5); each chosen by leave-one-sequence-out
// (docs/results/defaults.md, "Held out").
double method_joint_tolerance(Method method, double requested);
// The step extrapolation cap (TrackerOptions::step_extrapolation) a method uses when asked for
// -1 ("auto", the tracker's default); any other request is returned unchanged. robust: 1.9 (its
// re-estimated weights make every level crawl towards their fixed point; held out,
// docs/results/robust.md, "Cost"); the others: 1 (off, the settings their defaults were chosen
// with).
double method_step_extrapolation(Method method, double requested);
// The correction rounds (TrackerOptions::correction_rounds) a method uses when asked for -1
// ("auto", the tracker's default); any other request is returned unchanged. joint: 2, chosen
// held out (docs/results/rolling-shutter.md); robust: 1, its CPU budget (2 costs more than
// 1.3x weighted's, docs/results/defaults.md); the others: 1, as the paper's rules and depth
// alone were measured.
int method_correction_rounds(Method method, int requested);
// lambda of joint (S_II / S_DD) or scaled (kappa sigma_I^2 / sigma_D^2) from the scales of
// one linearization; 0 when the scales are degenerate (no valid depth residual).
double residual_lambda(Method method, const RgbdLinearizationStats& stats, const PolicyParameters& p);

}  // namespace bivo::odometry
