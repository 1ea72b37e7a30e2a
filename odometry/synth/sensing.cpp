// The sensor stage of the renderer: the noise-free views of odometry/synth/render.cpp turned
// into what a Kinect-class camera stores (sensor.h models, defects.h defects).
#include <algorithm>
#include <cmath>
#include <string>

#include "odometry/synth/defects.h"
#include "odometry/synth/noise_field.h"
#include "odometry/synth/random.h"
#include "odometry/synth/render.h"
#include "solvers/error.h"

namespace bivo::odometry::synth {

namespace {

// Random streams (with the noise seed and the frame index) so each noise source is independent.
constexpr std::uint64_t kDepthStream = 0xD0;
constexpr std::uint64_t kIntensityStream = 0x1A;
constexpr std::uint64_t kExposureStream = 0xE0;

}  // namespace

RenderedFrame sense(const SceneView& depth_view, const SceneView& colour_view, const RenderSettings& settings,
                    std::uint64_t frame_index) {
  const PinholeCamera& cam = settings.camera;
  const int W = cam.width, H = cam.height;
  const std::size_t n = static_cast<std::size_t>(W) * H;
  if (depth_view.true_depth.size() != n || depth_view.cos_incidence.size() != n || colour_view.radiance.size() != n) {
    throw Error("render_frame: a view's size is not the camera's " + std::to_string(W) + "x" + std::to_string(H));
  }
  const std::vector<Eigen::Vector3f>& radiance = colour_view.radiance;
  RenderedFrame out;
  out.width = W;
  out.height = H;
  out.rgb.assign(n * 3, 0);
  out.depth.assign(n, 0);
  out.true_depth = depth_view.true_depth;

  // Depth validity: range, incidence, then occluding edges (on the true depth) dilated.
  const DepthSensorModel& dm = settings.depth;
  const double min_cos = std::cos(dm.max_incidence_deg * M_PI / 180.0);
  std::vector<std::uint8_t> valid(static_cast<std::size_t>(W) * H, 0);
  for (std::size_t i = 0; i < valid.size(); ++i) {
    const double z = depth_view.true_depth[i];
    valid[i] = z > 0 && z >= dm.min_range_m && z <= dm.max_range_m && depth_view.cos_incidence[i] >= min_cos;
  }
  std::vector<std::uint8_t> edge(static_cast<std::size_t>(W) * H, 0);
  const auto jump = [&](std::size_t a, std::size_t b) {
    const float za = depth_view.true_depth[a], zb = depth_view.true_depth[b];
    if ((za > 0) != (zb > 0)) return true;
    return za > 0 && std::fabs(za - zb) > dm.occlusion_jump_rel * std::min(za, zb);
  };
  for (int v = 0; v < H; ++v) {
    for (int u = 0; u < W; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * W + u;
      if (u + 1 < W && jump(i, i + 1)) edge[i] = edge[i + 1] = 1;
      if (v + 1 < H && jump(i, i + W)) edge[i] = edge[i + W] = 1;
    }
  }
  const int band = std::max(0, dm.occlusion_band_px);
  const SensorDefects& defects = settings.defects;
  // Flying pixels come back from the pixels the band drops, so keep what was valid before it.
  const std::vector<std::uint8_t> before_band = defects.flying_pixels > 0 ? valid : std::vector<std::uint8_t>();
  for (int v = 0; v < H; ++v) {
    for (int u = 0; u < W; ++u) {
      if (!edge[static_cast<std::size_t>(v) * W + u]) continue;
      for (int y = std::max(0, v - band); y <= std::min(H - 1, v + band); ++y) {
        for (int x = std::max(0, u - band); x <= std::min(W - 1, u + band); ++x)
          valid[static_cast<std::size_t>(y) * W + x] = 0;
      }
    }
  }

  // The measured depth each flying pixel is given (0 elsewhere): part of the way from its own
  // surface to the band neighbour whose true depth differs most (a mixed return).
  std::vector<float> flying;
  if (!before_band.empty()) {
    flying.assign(n, 0.0f);
    for (int v = 0; v < H; ++v) {
      for (int u = 0; u < W; ++u) {
        const std::size_t i = static_cast<std::size_t>(v) * W + u;
        double t = 0;
        if (valid[i] || !before_band[i] || !flying_pixel(defects, settings.noise_seed, frame_index, i, &t)) continue;
        const double z = depth_view.true_depth[i];
        double other = z;
        for (int y = std::max(0, v - band); y <= std::min(H - 1, v + band); ++y) {
          for (int x = std::max(0, u - band); x <= std::min(W - 1, u + band); ++x) {
            const double zo = depth_view.true_depth[static_cast<std::size_t>(y) * W + x];
            if (zo > 0 && std::fabs(zo - z) > std::fabs(other - z)) other = zo;
          }
        }
        flying[i] = static_cast<float>(z + t * (other - z));
        valid[i] = 1;
      }
    }
  }

  const double fb = dm.ir_focal_px * dm.baseline_m;
  const std::vector<float> bias = defects.depth_bias()
                                      ? disparity_bias_field(defects, settings.noise_seed, W, H, cam.cx, cam.cy, fb)
                                      : std::vector<float>();
  const std::uint64_t depth_key = hash3(settings.noise_seed, kDepthStream, frame_index);
  std::vector<float> depth_noise =
      settings.sensor_noise ? correlated_normal_field(depth_key, W, H, dm.noise_correlation_px) : std::vector<float>();
  if (settings.sensor_noise && defects.static_noise_share > 0) {
    // The fixed pattern: the field of a frame index no sequence reaches, mixed in at unit variance.
    const std::vector<float> pattern =
        correlated_normal_field(hash3(settings.noise_seed, kDepthStream, ~0ull), W, H, dm.noise_correlation_px);
    const auto a = static_cast<float>(std::sqrt(1.0 - defects.static_noise_share));
    const auto b = static_cast<float>(std::sqrt(defects.static_noise_share));
    for (std::size_t i = 0; i < depth_noise.size(); ++i) depth_noise[i] = a * depth_noise[i] + b * pattern[i];
  }
  const double offset = disparity_offset(defects, settings.noise_seed, frame_index);
  const double p = defects.noise_exponent;
  std::size_t n_valid = 0;
  for (std::size_t i = 0; i < valid.size(); ++i) {
    if (!valid[i]) continue;
    double z = flying.empty() || flying[i] == 0.0f ? depth_view.true_depth[i] : flying[i];
    if (!bias.empty()) z = biased_depth(z, bias[i], fb);
    if (offset != 0.0) z = biased_depth(z, offset, fb);
    if (settings.sensor_noise) {
      // The z^2 case keeps its own expression (and rounding): renderings without defects keep their bytes.
      z += p == 2.0 ? dm.noise_coeff * z * z * depth_noise[i] : dm.noise_coeff * std::pow(z, p) * depth_noise[i];
      const double speckle = speckle_disparity_error(defects, settings.noise_seed, frame_index, i);
      if (speckle != 0.0 && z > 0) {
        const double disparity = fb / z + speckle;
        z = disparity > 0 ? fb / disparity : 0.0;
        if (z < dm.min_range_m || z > dm.max_range_m) continue;  // matched outside the range: no measurement
      }
      if (dm.disparity_step_px > 0 && z > 0) {
        const double disparity = std::round(fb / z / dm.disparity_step_px) * dm.disparity_step_px;
        z = disparity > 0 ? fb / disparity : 0.0;
      }
    }
    const double units = std::round(z * 5000.0);
    if (!(units >= 1.0 && units <= 65535.0)) continue;
    out.depth[i] = static_cast<std::uint16_t>(units);
    ++n_valid;
  }
  out.valid_depth_fraction = static_cast<double>(n_valid) / valid.size();

  const IntensitySensorModel& im = settings.intensity;
  out.exposure_gain = settings.sensor_noise && im.exposure_jitter > 0
                          ? std::exp(im.exposure_jitter * gaussian(settings.noise_seed, kExposureStream, frame_index))
                          : 1.0;
  if (defects.gain_step > 0) out.exposure_gain *= auto_exposure_gain(defects, settings.noise_seed, frame_index);
  std::vector<float> vignette;
  if (defects.vignetting > 0) {
    vignette.resize(radiance.size());
    for (int v = 0; v < H; ++v) {
      for (int u = 0; u < W; ++u) {
        vignette[static_cast<std::size_t>(v) * W + u] =
            static_cast<float>(1.0 - defects.vignetting * normalized_radius2(u, v, W, H, cam.cx, cam.cy));
      }
    }
  }
  const double scale = im.full_scale * out.exposure_gain;
  const std::uint64_t intensity_key = hash3(settings.noise_seed, kIntensityStream, frame_index);
  const float read2 = static_cast<float>(im.read_noise * im.read_noise);
  const float shot = static_cast<float>(im.shot_noise_gain);
  for (std::size_t i = 0; i < radiance.size(); ++i) {
    float value[3];
    for (int c = 0; c < 3; ++c) value[c] = static_cast<float>(scale) * radiance[i][c];
    if (!vignette.empty()) {
      for (int c = 0; c < 3; ++c) value[c] *= vignette[i];
    }
    if (settings.sensor_noise) {
      // Two independent pairs of normals per pixel: three channels, one spare.
      const NormalPair n01 = gaussian_pair(intensity_key, 2 * i), n23 = gaussian_pair(intensity_key, 2 * i + 1);
      const float n[3] = {n01.a, n01.b, n23.a};
      for (int c = 0; c < 3; ++c) value[c] += std::sqrt(read2 + shot * std::max(0.0f, value[c])) * n[c];
    }
    for (int c = 0; c < 3; ++c) {
      out.rgb[3 * i + c] = static_cast<std::uint8_t>(std::clamp(std::round(value[c]), 0.0f, 255.0f));
    }
  }
  return out;
}

}  // namespace bivo::odometry::synth
