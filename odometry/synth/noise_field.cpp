#include "odometry/synth/noise_field.h"

#include <cmath>

#include "odometry/synth/random.h"

namespace bivo::odometry::synth {

std::vector<float> correlated_normal_field(std::uint64_t key, int width, int height, double correlation_px) {
  const std::size_t n = static_cast<std::size_t>(width) * height;
  if (!(correlation_px > 0)) {
    std::vector<float> white(n);
    for (std::size_t i = 0; i < n; ++i) white[i] = gaussian_pair(key, i).a;
    return white;
  }
  const int r = static_cast<int>(std::ceil(3.0 * correlation_px));
  std::vector<float> kernel(2 * r + 1);
  double sum = 0, sum_sq = 0;
  for (int k = -r; k <= r; ++k) {
    kernel[k + r] = static_cast<float>(std::exp(-0.5 * k * k / (correlation_px * correlation_px)));
    sum += kernel[k + r];
  }
  for (float& k : kernel) {
    k = static_cast<float>(k / sum);
    sum_sq += static_cast<double>(k) * k;
  }
  // White noise on the image padded by r on every side, so every output pixel averages
  // the same number of independent values: each separable pass multiplies the variance
  // by sum_sq, and one scale restores unit variance everywhere, borders included.
  const int pw = width + 2 * r, ph = height + 2 * r;
  std::vector<float> white(static_cast<std::size_t>(pw) * ph);
  for (std::size_t i = 0; i < white.size(); ++i) white[i] = gaussian_pair(key, i).a;
  // Both passes accumulate tap by tap over whole rows (contiguous, vectorizable); every
  // output still sums its taps in the order k = 0 .. 2r.
  std::vector<float> rows(static_cast<std::size_t>(pw) * height, 0.0f);  // blurred along v
  for (int v = 0; v < height; ++v) {
    float* out = &rows[static_cast<std::size_t>(v) * pw];
    for (int k = 0; k <= 2 * r; ++k) {
      const float* in = &white[static_cast<std::size_t>(v + k) * pw];
      for (int u = 0; u < pw; ++u) out[u] += kernel[k] * in[u];
    }
  }
  const float scale = static_cast<float>(1.0 / sum_sq);  // 1 / sqrt(sum_sq^2)
  std::vector<float> field(n, 0.0f);
  for (int v = 0; v < height; ++v) {
    const float* row = &rows[static_cast<std::size_t>(v) * pw];
    float* out = &field[static_cast<std::size_t>(v) * width];
    for (int k = 0; k <= 2 * r; ++k) {
      for (int u = 0; u < width; ++u) out[u] += kernel[k] * row[u + k];
    }
    for (int u = 0; u < width; ++u) out[u] *= scale;
  }
  return field;
}

}  // namespace bivo::odometry::synth
