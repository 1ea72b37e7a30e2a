#include "odometry/rolling_shutter.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "odometry/image_statistics.h"

namespace bivo::odometry {

double row_time(int v, int height, double readout) { return ((v + 0.5) / height - 0.5) * readout; }

ImageF global_shutter_intensity(const ImageF& intensity, const ImageF& depth, const io::Intrinsics& K,
                                const solvers::se3::Vector6d& velocity, double readout) {
  const int w = intensity.width, h = intensity.height;
  // Row v's camera, as a map from the camera at the timestamp to the camera at row v's time.
  std::vector<Eigen::Matrix3f> R(static_cast<std::size_t>(h));
  std::vector<Eigen::Vector3f> t(static_cast<std::size_t>(h));
  for (int v = 0; v < h; ++v) {
    const Eigen::Isometry3d row_from_global = pose_after_delay(velocity, row_time(v, h, readout)).inverse();
    R[static_cast<std::size_t>(v)] = row_from_global.linear().cast<float>();
    t[static_cast<std::size_t>(v)] = row_from_global.translation().cast<float>();
  }
  const float fx = static_cast<float>(K.fx), fy = static_cast<float>(K.fy);
  const float cx = static_cast<float>(K.cx), cy = static_cast<float>(K.cy);
  float fallback = -1.0f;  // the median depth, once a row starts without depth
  ImageF out = intensity;
  for (int v = 0; v < h; ++v) {
    const float ray_y = (static_cast<float>(v) - cy) / fy;
    float z_last = 0.0f;
    for (int u = 0; u < w; ++u) {
      const float d = depth.at(u, v);
      if (d > 0.0f) {
        z_last = d;
      } else if (z_last == 0.0f) {
        if (fallback < 0.0f) fallback = static_cast<float>(median(depth, true));
        z_last = fallback;
      }
      if (!(z_last > 0.0f)) continue;
      const Eigen::Vector3f P(z_last * (static_cast<float>(u) - cx) / fx, z_last * ray_y, z_last);
      float x = static_cast<float>(u), y = static_cast<float>(v);
      bool inside = true;
      for (int pass = 0; pass < 2 && inside; ++pass) {
        const int row = pass == 0 ? v : std::min(static_cast<int>(y + 0.5f), h - 1);  // y in [0, h - 1]
        const Eigen::Vector3f q = R[static_cast<std::size_t>(row)] * P + t[static_cast<std::size_t>(row)];
        inside = q.z() > 0.0f;
        if (!inside) break;
        x = fx * q.x() / q.z() + cx;
        y = fy * q.y() / q.z() + cy;
        inside = x >= 0.0f && y >= 0.0f && x <= static_cast<float>(w - 1) && y <= static_cast<float>(h - 1);
      }
      if (!inside) continue;
      const int x0 = std::min(static_cast<int>(x), w - 2), y0 = std::min(static_cast<int>(y), h - 2);
      const float ax = x - static_cast<float>(x0), ay = y - static_cast<float>(y0);
      const float top = (1.0f - ax) * intensity.at(x0, y0) + ax * intensity.at(x0 + 1, y0);
      const float bottom = (1.0f - ax) * intensity.at(x0, y0 + 1) + ax * intensity.at(x0 + 1, y0 + 1);
      out.at(u, v) = (1.0f - ay) * top + ay * bottom;
    }
  }
  return out;
}

RgbdPyramid pyramid_at_timestamp(const RgbdPyramid& pyramid, const solvers::se3::Vector6d& velocity, bool retime,
                                 double readout) {
  const RgbdLevel& full = pyramid.levels.front();
  ImageF depth =
      retime ? retime_depth(full.depth, full.K, pose_after_delay(velocity, pyramid.depth_delay)) : full.depth;
  ImageF intensity =
      readout > 0.0 ? global_shutter_intensity(full.intensity, depth, full.K, velocity, readout) : full.intensity;
  RgbdPyramid out = pyramid_from_full_resolution(pyramid, std::move(intensity), std::move(depth));
  out.depth_delay = retime ? 0.0 : pyramid.depth_delay;  // retimed depth is taken at the timestamp
  return out;
}

}  // namespace bivo::odometry
