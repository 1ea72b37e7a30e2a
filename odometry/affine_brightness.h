#pragma once
// The affine brightness model of r_I (RgbdProblemOptions::affine_brightness): the current
// image's brightness relative to the reference's, I_2 ~ a I_1 + b, so that an auto-exposure
// or gain step is not read as photometric noise. Refit by weighted least squares on the stored
// residuals at every weight stage that weighs r_I and r_D together; the sums come from the
// kernels (KernelTable::brightness_sums), the correction is applied by them too.
#include "odometry/kernels/kernels.h"

namespace bivo::odometry {

struct BrightnessCorrection {
  double gain = 0.0, offset = 0.0;  // (da, db): r_I - (da I_1 + db) has no part along (I_1, 1)
  bool valid = false;               // false: no valid term, or I_1 constant over them
};

// The weighted least-squares fit of r_I on (I_1, 1) from its sums.
BrightnessCorrection solve_brightness(const BrightnessSums& sums);

// The fit to the stored r_I of `terms` (padded) buffer entries (under the stored w_I when
// weighted), applied to them: r_I -= da I_1 + db. sum_squares: their new sum of r_I^2 (left
// as it is when the fit is not valid).
BrightnessCorrection refit_stored_brightness(const KernelTable& kernels, const float* intensity, const TermBuffers& buf,
                                             std::size_t terms, bool weighted, int threads, double& sum_squares);

}  // namespace bivo::odometry
