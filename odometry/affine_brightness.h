#pragma once
// The brightness model of r_I (RgbdProblemOptions::affine_brightness): the current image's
// brightness relative to the reference's, I_2(y) ~ (a + c (rho_y^2 - rho_x^2)) I_1(x) + b,
// so that an auto-exposure or gain step (a, b) and a camera-fixed radial fall-off (c, the
// vignetting 1 - k rho^2 of both images to first order: c = -a k) are not read as
// photometric noise, nor the fall-off as a cue of no motion. Refit by weighted least squares
// on the stored residuals at every weight stage that weighs r_I and r_D together; the sums
// come from the kernels (KernelTable::brightness_sums), the correction is applied by them too.
#include "odometry/kernels/kernels.h"

namespace bivo::odometry {

struct BrightnessCorrection {
  // (da, db, dc): r_I - (da I_1 + db + dc q) has no part along (I_1, 1, q), q = I_1 (rho_y^2 -
  // rho_x^2); dc = 0 without the radial term or when q does not separate from (I_1, 1).
  double gain = 0.0, offset = 0.0, radial = 0.0;
  bool valid = false;  // false: no valid term, or I_1 constant over them
};

// The ridge on the radial term (RgbdProblemOptions::radial_prior): strength times the sum of
// the weights times (c + dc)^2 joins the fit, c the present coefficient.
struct RadialPrior {
  double strength = 0.0, current = 0.0;
};

// A fit whose gain a would fall below this is refused (not valid): I_2 at the warped points no
// longer follows I_1 (an image without contrast, or a pose far from aligning them), which no
// brightness change explains; a = 0 would explain every r_I away and leave no residual scale.
constexpr double kMinBrightnessGain = 0.1;

// The weighted least-squares fit of r_I on (I_1, 1) (and q when `radial`) from its sums.
BrightnessCorrection solve_brightness(const BrightnessSums& sums, bool radial, const RadialPrior& prior = {});

// The fit to the stored r_I of `terms` (padded) buffer entries, applied to them, unless the gain
// would fall below kMinBrightnessGain from the present `gain`. sum_squares: their new sum of r_I^2
// (left as it is when the fit is not valid).
BrightnessCorrection refit_stored_brightness(const KernelTable& kernels, const BrightnessFit& fit,
                                             const RadialPrior& prior, double gain, const TermBuffers& buf,
                                             std::size_t terms, int threads, double& sum_squares);

// rho_x^2 of the reference terms (padded to `padded` entries with 0) by `kernels`
// (KernelTable::squared_radii: as the warp forms rho_y^2, so that q = 0 at the identity).
PooledFloats squared_radii(const KernelTable& kernels, const ReferenceArrays& ref, std::size_t padded);

}  // namespace bivo::odometry
