#pragma once
// The affine brightness model of r_I (RgbdProblemOptions::affine_brightness): the current
// image's brightness relative to the reference's, I_2 ~ a I_1 + b, so that an auto-exposure
// or gain step is not read as photometric noise. Refit by weighted least squares on the stored
// residuals at every weight stage that weighs r_I and r_D together.
#include <cstddef>
#include <cstdint>

namespace bivo::odometry {

struct BrightnessCorrection {
  double gain = 0.0, offset = 0.0;  // (da, db): r_I - (da I_1 + db) has no part along (I_1, 1)
  bool valid = false;               // false: no valid term, or I_1 constant over them
};

// The weighted least-squares fit of r_I on (I_1, 1) over the terms whose flag has bit 0 set
// (r_I valid); weights null: unit weights.
BrightnessCorrection fit_brightness(const float* intensity, const float* r_i, const std::uint8_t* flags,
                                    const float* weights, std::size_t n);

// r_I -= da I_1 + db on the valid terms; returns the new sum of r_I^2 over them.
double apply_brightness(const BrightnessCorrection& c, const float* intensity, float* r_i, const std::uint8_t* flags,
                        std::size_t n);

}  // namespace bivo::odometry
