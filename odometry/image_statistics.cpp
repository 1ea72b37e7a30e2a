#include "odometry/image_statistics.h"

#include <algorithm>
#include <cmath>

namespace bivo::odometry {

double complexity_metric(const ImageF& image, bool skip_missing) {
  double sum_x = 0.0, sum_y = 0.0;
  long long used_x = 0, used_y = 0;
  for (int y = 1; y + 1 < image.height; ++y) {
    for (int x = 1; x + 1 < image.width; ++x) {
      const float l = image.at(x - 1, y), r = image.at(x + 1, y);
      const float u = image.at(x, y - 1), d = image.at(x, y + 1);
      if (!skip_missing || (l > 0.0f && r > 0.0f)) {
        sum_x += std::abs(double(r) - l);
        ++used_x;
      }
      if (!skip_missing || (u > 0.0f && d > 0.0f)) {
        sum_y += std::abs(double(d) - u);
        ++used_y;
      }
    }
  }
  return (used_x > 0 ? sum_x / used_x : 0.0) + (used_y > 0 ? sum_y / used_y : 0.0);
}

double variance(const ImageF& image, bool skip_missing) {
  double s = 0.0, s2 = 0.0;
  long long n = 0;
  for (float v : image.data) {
    if (skip_missing && !(v > 0.0f)) continue;
    s += v;
    s2 += double(v) * v;
    ++n;
  }
  if (n == 0) return 0.0;
  const double mean = s / n;
  return std::max(0.0, s2 / n - mean * mean);
}

double median(const ImageF& image, bool skip_missing) {
  std::vector<float> v;
  v.reserve(image.data.size());
  for (float x : image.data) {
    if (!skip_missing || x > 0.0f) v.push_back(x);
  }
  if (v.empty()) return 0.0;
  const std::size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + mid, v.end());
  if (v.size() % 2 == 1) return v[mid];
  const float upper = v[mid];
  const float lower = *std::max_element(v.begin(), v.begin() + mid);
  return 0.5 * (double(lower) + upper);
}

FrameStatistics frame_statistics(const RgbdLevel& level) {
  FrameStatistics s;
  s.pi_intensity = complexity_metric(level.intensity, false);
  s.pi_depth = complexity_metric(level.depth, true);
  s.var_intensity = variance(level.intensity, false);
  s.var_depth = variance(level.depth, true);
  s.median_intensity = median(level.intensity, false);
  s.median_depth = median(level.depth, true);
  long long valid = 0;
  for (float d : level.depth.data) valid += d > 0.0f;
  s.valid_depth_fraction = level.depth.data.empty() ? 0.0 : double(valid) / level.depth.data.size();
  return s;
}

}  // namespace bivo::odometry
