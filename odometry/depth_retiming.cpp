#include "odometry/depth_retiming.h"

#include <limits>
#include <vector>

#include "solvers/geometry/se3.h"

namespace bivo::odometry {

namespace se3 = solvers::se3;

Eigen::Isometry3d pose_after_delay(const se3::Vector6d& velocity, double delay) {
  return se3::exp(se3::Vector6d(-delay * velocity));
}

ImageF retime_depth(const ImageF& depth, const io::Intrinsics& K, const Eigen::Isometry3d& colour_from_depth) {
  return retime_depth(depth, K, colour_from_depth, default_kernels().isa);
}

ImageF retime_depth(const ImageF& depth, const io::Intrinsics& K, const Eigen::Isometry3d& colour_from_depth,
                    KernelIsa isa) {
  const int w = depth.width, h = depth.height;
  constexpr float kNone = std::numeric_limits<float>::infinity();
  ImageF out;
  out.width = w;
  out.height = h;
  out.data.assign(depth.data.size(), kNone);
  RetimeDepthParams p;
  const Eigen::Matrix3f R = colour_from_depth.linear().cast<float>();
  const Eigen::Vector3f t = colour_from_depth.translation().cast<float>();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) p.pose[3 * i + j] = R(i, j);
    p.pose[9 + i] = t(i);
  }
  p.fx = static_cast<float>(K.fx);
  p.fy = static_cast<float>(K.fy);
  p.cx = static_cast<float>(K.cx);
  p.cy = static_cast<float>(K.cy);
  std::vector<float> rays(static_cast<std::size_t>(w) + kLaneGroup), row(rays.size() + 2);
  for (std::size_t u = 0; u < rays.size(); ++u) rays[u] = (static_cast<float>(u) - p.cx) / p.fx;
  p.depth = depth.data.data();
  p.rays = rays.data();
  p.row = row.data();
  p.out = out.data.data();
  p.width = w;
  p.height = h;
  kernels(isa).retime_depth_rows(p, 0, h);
  for (float& z : out.data) {
    if (z == kNone) z = 0.0f;
  }
  return out;
}

}  // namespace bivo::odometry
