#pragma once
// Ray-casting renderer of one synthetic RGB-D frame: analytic ray-rectangle intersections,
// supersampled and mip-filtered colour (anti-aliased), depth at the pixel centre, then the
// sensor models of synth/sensor.h.
#include <cstdint>
#include <vector>

#include <Eigen/Geometry>

#include "odometry/synth/defects.h"
#include "odometry/synth/scene.h"
#include "odometry/synth/sensor.h"

namespace bivo::odometry::synth {

struct RenderSettings {
  PinholeCamera camera;
  DepthSensorModel depth;
  IntensitySensorModel intensity;
  int supersampling = 2;     // n x n colour samples per pixel (1 = none)
  bool sensor_noise = true;  // false: no random noise, no disparity quantization, unit exposure
  std::uint64_t noise_seed = 1;
  SensorDefects defects;  // all off by default
};

struct RenderedFrame {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;     // 3 per pixel, row-major
  std::vector<std::uint16_t> depth;  // TUM units: 5000 per metre, 0 = no measurement
  std::vector<float> true_depth;     // noise-free z [m] of the centre ray, 0 = no surface hit
  double exposure_gain = 1.0;
  double valid_depth_fraction = 0.0;  // share of pixels with a depth measurement
};

// Throws bivo::Error naming the setting when a camera or sensor parameter is outside its
// range (NaN, negative noise, max range <= min range, an image above input_limits()...).
// render_frame checks; callers rendering many frames check once before any work.
void validate(const RenderSettings& settings);

// The noise-free image of one exposure: true depth and incidence of every pixel's centre
// ray, and (when asked) its radiance (albedo x shading, before exposure).
struct SceneView {
  int width = 0, height = 0;
  std::vector<float> true_depth, cos_incidence;
  std::vector<Eigen::Vector3f> radiance;
};

// The view from camera-to-world pose row_poses[0] (global shutter), or row v from
// row_poses[v] (one pose per image row: a rolling shutter). Throws on another count.
SceneView view_scene(const Scene& scene, const std::vector<Eigen::Isometry3d>& row_poses,
                     const RenderSettings& settings, bool with_radiance);

// The sensor stage: depth (validity, bias, noise, quantization) from depth_view, colour
// (vignetting, exposure, noise, 8 bits) from colour_view's radiance; `frame_index` selects
// the noise realization with settings.noise_seed.
RenderedFrame sense(const SceneView& depth_view, const SceneView& colour_view, const RenderSettings& settings,
                    std::uint64_t frame_index);

// Renders the scene seen by a camera at pose T_wc (camera-to-world). `frame_index` selects
// the noise realization (with settings.noise_seed), so frames are reproducible one by one.
RenderedFrame render_frame(const Scene& scene, const Eigen::Isometry3d& T_wc, const RenderSettings& settings,
                           std::uint64_t frame_index);

}  // namespace bivo::odometry::synth
