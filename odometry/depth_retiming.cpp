#include "odometry/depth_retiming.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "solvers/geometry/se3.h"

namespace bivo::odometry {

namespace se3 = solvers::se3;

Eigen::Isometry3d pose_after_delay(const se3::Vector6d& velocity, double delay) {
  return se3::exp(se3::Vector6d(-delay * velocity));
}

namespace {

// Depth change per pixel through z from its neighbours a and b (central difference), 0 unless
// both are valid and within 5 % of z (one surface).
float slope(float a, float z, float b) {
  const float tolerance = 0.05f * z;
  return a > 0.0f && b > 0.0f && std::fabs(a - z) < tolerance && std::fabs(b - z) < tolerance ? 0.5f * (b - a) : 0.0f;
}

}  // namespace

ImageF retime_depth(const ImageF& depth, const io::Intrinsics& K, const Eigen::Isometry3d& colour_from_depth) {
  const int w = depth.width, h = depth.height;
  constexpr float kNone = std::numeric_limits<float>::infinity();
  ImageF out;
  out.width = w;
  out.height = h;
  out.data.assign(depth.data.size(), kNone);
  const Eigen::Matrix3f R = colour_from_depth.linear().cast<float>();
  const Eigen::Vector3f t = colour_from_depth.translation().cast<float>();
  const float fx = static_cast<float>(K.fx), fy = static_cast<float>(K.fy);
  const float cx = static_cast<float>(K.cx), cy = static_cast<float>(K.cy);
  std::vector<float> ray_x(static_cast<std::size_t>(w));
  for (int u = 0; u < w; ++u) ray_x[static_cast<std::size_t>(u)] = (static_cast<float>(u) - cx) / fx;
  for (int v = 0; v < h; ++v) {
    // q = z R [ray_x, ray_y, 1] + t, the row's part of R [., ray_y, 1] once per row
    const float ray_y = (static_cast<float>(v) - cy) / fy;
    const float bx = R(0, 1) * ray_y + R(0, 2), by = R(1, 1) * ray_y + R(1, 2), bz = R(2, 1) * ray_y + R(2, 2);
    const float* row = depth.data.data() + static_cast<std::size_t>(v) * static_cast<std::size_t>(w);
    const float* up = v > 0 ? row - w : nullptr;
    const float* down = v + 1 < h ? row + w : nullptr;
    for (int u = 0; u < w; ++u) {
      const float z = row[u], rx = ray_x[static_cast<std::size_t>(u)];
      if (!(z > 0.0f)) continue;
      const float qz = z * (R(2, 0) * rx + bz) + t.z();
      if (!(qz > 0.0f)) continue;
      const float inv_z = 1.0f / qz;
      const float x = fx * (z * (R(0, 0) * rx + bx) + t.x()) * inv_z + cx;
      const float y = fy * (z * (R(1, 0) * rx + by) + t.y()) * inv_z + cy;
      if (!(x > -0.5f && x < static_cast<float>(w) - 0.5f && y > -0.5f && y < static_cast<float>(h) - 0.5f)) continue;
      const int xi = static_cast<int>(x + 0.5f), yi = static_cast<int>(y + 0.5f);  // the nearest pixel
      // The surface's depth at that pixel's centre, not at the point: the depth image's slope
      // (central differences on one surface) over the sub-pixel offset.
      const float gx = u > 0 && u + 1 < w ? slope(row[u - 1], z, row[u + 1]) : 0.0f;
      const float gy = up && down ? slope(up[u], z, down[u]) : 0.0f;
      float& slot = out.at(xi, yi);
      slot = std::min(slot, qz + gx * (static_cast<float>(xi) - x) + gy * (static_cast<float>(yi) - y));
    }
  }
  for (float& z : out.data) {
    if (z == kNone) z = 0.0f;
  }
  return out;
}

}  // namespace bivo::odometry
