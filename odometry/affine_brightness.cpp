#include "odometry/affine_brightness.h"

namespace bivo::odometry {

BrightnessCorrection fit_brightness(const float* intensity, const float* r_i, const std::uint8_t* flags,
                                    const float* weights, std::size_t n) {
  double s_xx = 0.0, s_x = 0.0, s_1 = 0.0, s_xr = 0.0, s_r = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    if (!(flags[k] & 1)) continue;
    const double w = weights ? weights[k] : 1.0, x = intensity[k], r = r_i[k];
    s_xx += w * x * x;
    s_x += w * x;
    s_1 += w;
    s_xr += w * x * r;
    s_r += w * r;
  }
  const double det = s_xx * s_1 - s_x * s_x;
  BrightnessCorrection c;
  if (!(s_1 > 0.0) || !(det > 1e-9 * s_xx * s_1)) return c;
  c.gain = (s_1 * s_xr - s_x * s_r) / det;
  c.offset = (s_xx * s_r - s_x * s_xr) / det;
  c.valid = true;
  return c;
}

double apply_brightness(const BrightnessCorrection& c, const float* intensity, float* r_i, const std::uint8_t* flags,
                        std::size_t n) {
  double ss = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    if (!(flags[k] & 1)) continue;
    r_i[k] -= static_cast<float>(c.gain * intensity[k] + c.offset);
    ss += double(r_i[k]) * r_i[k];
  }
  return ss;
}

}  // namespace bivo::odometry
