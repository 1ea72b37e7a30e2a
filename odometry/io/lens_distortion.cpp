#include "odometry/io/lens_distortion.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "odometry/io/tum_dataset.h"
#include "solvers/error.h"

namespace bivo::odometry::io {

std::array<double, 2> Distortion::distort(double x, double y) const {
  const double r2 = x * x + y * y;
  const double g = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
  return {g * x + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x), g * y + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y};
}

Distortion distortion_for_sequence(const std::string& name_or_path) {
  const auto has = [&](const char* s) { return name_or_path.find(s) != std::string::npos; };
  // The TUM RGB-D benchmark's calibration page (the same source as the intrinsics presets).
  if (has("freiburg1") || has("fr1")) return {0.2624, -0.9531, -0.0054, 0.0026, 1.1633};
  if (has("freiburg2") || has("fr2")) return {0.2312, -0.7849, -0.0033, -0.0001, 0.9172};
  return {};
}

Distortion parse_distortion(const std::string& text) {
  std::istringstream s(text);
  std::string first;
  if ((s >> first) && first == "none") {
    std::string extra;
    if (s >> extra) throw Error("distortion '" + text + "': unexpected extra field '" + extra + "'");
    return {};
  }
  std::istringstream all(text);
  double v[5];
  for (double& x : v) {
    if (!(all >> x) || !std::isfinite(x)) {
      throw Error("distortion '" + text + "': expected five numbers 'k1 k2 p1 p2 k3' or 'none'");
    }
  }
  std::string extra;
  if (all >> extra) throw Error("distortion '" + text + "': unexpected extra field '" + extra + "'");
  return {v[0], v[1], v[2], v[3], v[4]};
}

Undistortion::Undistortion(const Intrinsics& K, const Distortion& d, int width, int height)
    : K_(K), d_(d), width_(width), height_(height), identity_(d.is_identity()) {
  if (width < 2 || height < 2) {
    throw Error("undistortion: image size " + std::to_string(width) + "x" + std::to_string(height) + " is too small");
  }
  if (identity_) return;
  const std::size_t n = static_cast<std::size_t>(width) * height;
  cell_.resize(n);
  fu_.resize(n);
  fv_.resize(n);
  nearest_.resize(n);
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * width + u;
      const auto [su, sv] = source(u, v);
      const bool inside = su >= 0.0 && su <= width - 1.0 && sv >= 0.0 && sv <= height - 1.0;
      nearest_[i] = inside ? static_cast<std::int32_t>(std::lround(sv) * width + std::lround(su)) : -1;
      // The bilinear cell: clamped so that its right/bottom neighbour exists (a lens model so
      // strong that the position overflows reads the image's corner).
      const double cu = std::isfinite(su) ? std::clamp(su, 0.0, width - 1.0) : 0.0;
      const double cv = std::isfinite(sv) ? std::clamp(sv, 0.0, height - 1.0) : 0.0;
      const int u0 = std::min(static_cast<int>(cu), width - 2), v0 = std::min(static_cast<int>(cv), height - 2);
      cell_[i] = v0 * width + u0;
      fu_[i] = static_cast<float>(cu - u0);
      fv_[i] = static_cast<float>(cv - v0);
    }
  }
}

std::array<double, 2> Undistortion::source(int u, int v) const {
  const auto [xd, yd] = d_.distort((u - K_.cx) / K_.fx, (v - K_.cy) / K_.fy);
  return {K_.fx * xd + K_.cx, K_.fy * yd + K_.cy};
}

void Undistortion::apply(RgbdImage& image) const {
  if (image.width != width_ || image.height != height_) {
    throw Error("undistortion: frame at t = " + std::to_string(image.timestamp) + " is " + std::to_string(image.width) +
                "x" + std::to_string(image.height) + ", the map was built for " + std::to_string(width_) + "x" +
                std::to_string(height_));
  }
  if (identity_) return;
  const std::size_t n = cell_.size();
  std::vector<float>& intensity = spare_intensity_;
  std::vector<float>& depth = spare_depth_;
  intensity.resize(n);
  depth.resize(n);
  const float* I = image.intensity.data();
  const float* D = image.depth.data();
  for (std::size_t i = 0; i < n; ++i) {
    const float* p = I + cell_[i];
    const float a = fu_[i], b = fv_[i];
    intensity[i] = (1.0f - b) * ((1.0f - a) * p[0] + a * p[1]) + b * ((1.0f - a) * p[width_] + a * p[width_ + 1]);
    depth[i] = nearest_[i] >= 0 ? D[nearest_[i]] : 0.0f;
  }
  image.intensity.swap(intensity);
  image.depth.swap(depth);
}

}  // namespace bivo::odometry::io
