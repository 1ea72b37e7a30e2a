#include "odometry/rolling_shutter.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "odometry/image_statistics.h"

namespace bivo::odometry {

double row_time(int v, int height, double readout) { return ((v + 0.5) / height - 0.5) * readout; }

ImageF global_shutter_intensity(const ImageF& intensity, const ImageF& depth, const io::Intrinsics& K,
                                const solvers::se3::Vector6d& velocity, double readout, int threads) {
  return global_shutter_intensity(intensity, depth, K, velocity, readout, default_kernels().isa, threads);
}

ImageF global_shutter_intensity(const ImageF& intensity, const ImageF& depth, const io::Intrinsics& K,
                                const solvers::se3::Vector6d& velocity, double readout, KernelIsa isa, int threads) {
  const int w = intensity.width, h = intensity.height;
  // Row v's camera, as a map from the camera at the timestamp to the camera at row v's time:
  // R row-major, then t (GlobalShutterParams::pose).
  std::vector<float> pose(12 * static_cast<std::size_t>(h));
  for (int v = 0; v < h; ++v) {
    const Eigen::Isometry3d row_from_global = pose_after_delay(velocity, row_time(v, h, readout)).inverse();
    const Eigen::Matrix3f R = row_from_global.linear().cast<float>();
    const Eigen::Vector3f t = row_from_global.translation().cast<float>();
    float* p = pose.data() + 12 * static_cast<std::size_t>(v);
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) p[3 * i + j] = R(i, j);
      p[9 + i] = t(i);
    }
  }
  // A row that starts without depth takes the image's median until its first valid depth.
  float fallback = 0.0f;
  for (int v = 0; v < h; ++v) {
    if (!(depth.at(0, v) > 0.0f)) {
      fallback = static_cast<float>(median(depth, true));
      break;
    }
  }
  std::vector<float> columns(static_cast<std::size_t>(w) + kLaneGroup);
  for (std::size_t u = 0; u < columns.size(); ++u) columns[u] = static_cast<float>(u);
  ImageF out = intensity;
  GlobalShutterParams p;
  p.intensity = intensity.data.data();
  p.depth = depth.data.data();
  p.fallback = fallback;
  p.pose = pose.data();
  p.columns = columns.data();
  p.out = out.data.data();
  p.width = w;
  p.height = h;
  p.fx = static_cast<float>(K.fx);
  p.fy = static_cast<float>(K.fy);
  p.cx = static_cast<float>(K.cx);
  p.cy = static_cast<float>(K.cy);
  // Each row is moved on its own (its row_depth scratch per chunk of rows).
  constexpr int kRowsPerChunk = 16;
  const KernelTable& table = kernels(isa);
  for_each_chunk((h + kRowsPerChunk - 1) / kRowsPerChunk, threads, [&](int c) {
    std::vector<float> row_depth(columns.size());
    GlobalShutterParams rows = p;
    rows.row_depth = row_depth.data();
    table.global_shutter_rows(rows, c * kRowsPerChunk, std::min(h, (c + 1) * kRowsPerChunk));
  });
  return out;
}

RgbdPyramid pyramid_at_timestamp(const RgbdPyramid& pyramid, const solvers::se3::Vector6d& velocity, bool retime,
                                 double readout, int threads) {
  const RgbdLevel& full = pyramid.levels.front();
  ImageF depth =
      retime ? retime_depth(full.depth, full.K, pose_after_delay(velocity, pyramid.depth_delay)) : full.depth;
  ImageF intensity = readout > 0.0 ? global_shutter_intensity(full.intensity, depth, full.K, velocity, readout, threads)
                                   : full.intensity;
  RgbdPyramid out = pyramid_from_full_resolution(pyramid, std::move(intensity), std::move(depth));
  out.depth_delay = retime ? 0.0 : pyramid.depth_delay;  // retimed depth is taken at the timestamp
  return out;
}

}  // namespace bivo::odometry
