#include "odometry/io/vignetting.h"

#include <algorithm>
#include <string>

#include "solvers/error.h"

namespace bivo::odometry::io {

double normalized_radius2(double u, double v, int width, int height, double cx, double cy) {
  const double dx = std::max(cx, width - 1 - cx), dy = std::max(cy, height - 1 - cy);
  return ((u - cx) * (u - cx) + (v - cy) * (v - cy)) / (dx * dx + dy * dy);
}

void divide_out_vignetting(RgbdImage& image, double k, const Intrinsics& K) {
  if (!(k >= 0.0 && k < 1.0)) throw Error("vignetting fall-off must be in [0, 1), got " + std::to_string(k));
  if (k == 0.0) return;
  const int W = image.width, H = image.height;
  for (int v = 0; v < H; ++v) {
    float* row = image.intensity.data() + static_cast<std::size_t>(v) * W;
    for (int u = 0; u < W; ++u) {
      row[u] = static_cast<float>(row[u] / (1.0 - k * normalized_radius2(u, v, W, H, K.cx, K.cy)));
    }
  }
}

}  // namespace bivo::odometry::io
