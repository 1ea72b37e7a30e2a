#include "odometry/synth/render.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include "odometry/io/input_limits.h"
#include "odometry/synth/noise_field.h"
#include "odometry/synth/random.h"
#include "solvers/error.h"

namespace bivo::odometry::synth {

namespace {

// Random streams (with the noise seed and the frame index) so each noise source is independent.
constexpr std::uint64_t kDepthStream = 0xD0;
constexpr std::uint64_t kIntensityStream = 0x1A;
constexpr std::uint64_t kExposureStream = 0xE0;

// A scene rectangle expressed in the camera frame, with what the intersection test needs.
struct CameraPanel {
  Eigen::Vector3d origin, edge_u, edge_v, normal;
  double plane_offset;           // normal . origin
  double inv_len2_u, inv_len2_v; // 1 / |edge|^2
  double len_u, len_v;
  int material;
  std::uint64_t key;             // which poster each texture cell shows (scene seed, panel index)
};

struct Hit {
  int panel = -1;
  double z = 0.0;     // depth along the optical axis (the ray has unit z component)
  double a = 0, b = 0;
};

// Nearest intersection of the ray t * (x, y, 1), t > 0, with the panels.
Hit cast(const std::vector<CameraPanel>& panels, const Eigen::Vector3d& ray) {
  Hit best;
  best.z = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < panels.size(); ++i) {
    const CameraPanel& p = panels[i];
    const double denom = p.normal.dot(ray);
    if (std::fabs(denom) < 1e-12) continue;
    const double t = p.plane_offset / denom;
    if (t <= 1e-6 || t >= best.z) continue;
    const Eigen::Vector3d q = t * ray - p.origin;
    const double a = q.dot(p.edge_u) * p.inv_len2_u;
    if (a < 0.0 || a > 1.0) continue;
    const double b = q.dot(p.edge_v) * p.inv_len2_v;
    if (b < 0.0 || b > 1.0) continue;
    best.panel = static_cast<int>(i);
    best.z = t;
    best.a = a;
    best.b = b;
  }
  if (best.panel < 0) best.z = 0.0;
  return best;
}

// Throws unless lo <= value <= hi (NaN fails every comparison, so it is refused too).
void check_range(double value, double lo, double hi, const char* what) {
  if (!(value >= lo && value <= hi)) {
    std::ostringstream m;
    m << "render settings: " << what << " must be in [" << lo << ", " << hi << "], got " << value;
    throw Error(m.str());
  }
}

}  // namespace

void validate(const RenderSettings& s) {
  const double kBig = std::numeric_limits<double>::max();
  const PinholeCamera& cam = s.camera;
  io::check_image_size(cam.width, cam.height, "render settings: camera");
  check_range(cam.fx, 1e-3, kBig, "fx");
  check_range(cam.fy, 1e-3, kBig, "fy");
  check_range(cam.cx, -kBig, kBig, "cx");
  check_range(cam.cy, -kBig, kBig, "cy");
  check_range(s.supersampling, 1, 8, "supersampling");
  const DepthSensorModel& d = s.depth;
  check_range(d.noise_coeff, 0, 1e3, "depth noise coefficient [1/m]");
  check_range(d.baseline_m, 1e-6, 1e3, "baseline [m]");
  check_range(d.disparity_step_px, 0, 1e3, "disparity step [px]");
  check_range(d.min_range_m, 0, 1e4, "minimum range [m]");
  if (!(d.max_range_m > d.min_range_m)) {
    std::ostringstream m;
    m << "render settings: maximum range " << d.max_range_m << " m must exceed the minimum range " << d.min_range_m
      << " m";
    throw Error(m.str());
  }
  check_range(d.max_range_m, 0, 1e4, "maximum range [m]");
  check_range(d.max_incidence_deg, 0, 90, "maximum incidence [deg]");
  check_range(d.occlusion_jump_rel, 0, 1e3, "occlusion jump (relative)");
  check_range(d.occlusion_band_px, 0, 64, "occlusion band [px]");
  const IntensitySensorModel& im = s.intensity;
  check_range(im.read_noise, 0, 1e4, "read noise [gray levels]");
  check_range(im.shot_noise_gain, 0, 1e4, "shot-noise gain");
  // exp(2 x 8 sigma) ~ 1e7 keeps every exposed radiance finite in float.
  check_range(im.exposure_jitter, 0, 2, "exposure jitter (sigma of the log gain)");
  check_range(im.full_scale, 1e-3, 1e4, "full scale [gray levels]");
}

RenderedFrame render_frame(const Scene& scene, const Eigen::Isometry3d& T_wc, const RenderSettings& settings,
                           std::uint64_t frame_index) {
  const PinholeCamera& cam = settings.camera;
  validate(settings);
  if (!T_wc.matrix().allFinite()) throw Error("render_frame: non-finite camera pose");

  const Eigen::Matrix3d R_cw = T_wc.linear().transpose();
  const Eigen::Vector3d t_cw = -R_cw * T_wc.translation();
  // Panels wholly outside the view frustum (all corners beyond one side plane, padded by
  // a pixel for the supersampled rays) are not cast against: the zig-zag has 24 panels.
  const double pad = 1.0;
  const double kx0 = (-pad - cam.cx) / cam.fx, kx1 = (cam.width - 1 + pad - cam.cx) / cam.fx;
  const double ky0 = (-pad - cam.cy) / cam.fy, ky1 = (cam.height - 1 + pad - cam.cy) / cam.fy;
  const auto outside_frustum = [&](const Panel& p) {
    bool out[4] = {true, true, true, true};
    for (const Eigen::Vector3d& w : {p.origin, Eigen::Vector3d(p.origin + p.edge_u),
                                     Eigen::Vector3d(p.origin + p.edge_v), Eigen::Vector3d(p.origin + p.edge_u + p.edge_v)}) {
      const Eigen::Vector3d q = R_cw * w + t_cw;
      out[0] = out[0] && q.x() < kx0 * q.z();
      out[1] = out[1] && q.x() > kx1 * q.z();
      out[2] = out[2] && q.y() < ky0 * q.z();
      out[3] = out[3] && q.y() > ky1 * q.z();
    }
    return out[0] || out[1] || out[2] || out[3];
  };
  std::vector<CameraPanel> panels;
  for (const Panel& p : scene.panels) {
    if (outside_frustum(p)) continue;
    CameraPanel c;
    c.origin = R_cw * p.origin + t_cw;
    c.edge_u = R_cw * p.edge_u;
    c.edge_v = R_cw * p.edge_v;
    c.normal = R_cw * p.normal();
    c.plane_offset = c.normal.dot(c.origin);
    c.len_u = p.edge_u.norm();
    c.len_v = p.edge_v.norm();
    c.inv_len2_u = 1.0 / (c.len_u * c.len_u);
    c.inv_len2_v = 1.0 / (c.len_v * c.len_v);
    c.material = p.material;
    c.key = hash3(scene.seed, 0xCE11, static_cast<std::uint64_t>(&p - scene.panels.data()));
    panels.push_back(c);
  }
  const Eigen::Vector3d light_c = R_cw * scene.light_position + t_cw;

  const int W = cam.width, H = cam.height, ss = settings.supersampling;
  const double focal = std::sqrt(cam.fx * cam.fy);
  RenderedFrame out;
  out.width = W;
  out.height = H;
  out.rgb.assign(static_cast<std::size_t>(W) * H * 3, 0);
  out.depth.assign(static_cast<std::size_t>(W) * H, 0);
  out.true_depth.assign(static_cast<std::size_t>(W) * H, 0.0f);
  std::vector<float> cos_incidence(static_cast<std::size_t>(W) * H, 0.0f);
  std::vector<Eigen::Vector3f> radiance(static_cast<std::size_t>(W) * H);

  // Radiance (albedo x shading, before exposure) seen along one ray, with the texture
  // prefiltered over the sample's footprint of `footprint_px` pixels.
  const auto shade = [&](const Eigen::Vector3d& ray, const Hit& hit, double footprint_px) -> Eigen::Vector3f {
    if (hit.panel < 0) return scene.background;
    const CameraPanel& p = panels[hit.panel];
    const Material& m = scene.materials[p.material];
    const double cos_inc = std::fabs(p.normal.dot(ray)) / ray.norm();
    const double u_m = hit.a * p.len_u, v_m = hit.b * p.len_v;
    const double cu = std::floor(u_m / m.tile_u_m), cv = std::floor(v_m / m.tile_v_m);
    const std::uint64_t cell = (static_cast<std::uint64_t>(cu) << 32) ^ static_cast<std::uint64_t>(cv);
    const int tex = m.textures.size() == 1
                        ? m.textures[0]
                        : m.textures[mix64(p.key ^ cell) % m.textures.size()];
    const MipTexture& T = scene.textures[tex];
    // Footprint on the surface: z/f per pixel across the ray, stretched by 1/cos along
    // the slope; the geometric mean of the two makes an isotropic filter width.
    const double footprint_m = hit.z * footprint_px / focal / std::sqrt(std::max(cos_inc, 0.05));
    const float texels = static_cast<float>(footprint_m / m.tile_u_m * T.width());
    const Eigen::Vector3f albedo = T.sample(static_cast<float>(u_m / m.tile_u_m - cu),
                                            static_cast<float>(v_m / m.tile_v_m - cv), texels);
    const Eigen::Vector3d n = p.normal.dot(ray) > 0 ? Eigen::Vector3d(-p.normal) : p.normal;
    const Eigen::Vector3d to_light = light_c - hit.z * ray;  // rays have unit z: hit.z * ray is the point
    const double r = to_light.norm();
    const double falloff = scene.light_reference_m * scene.light_reference_m / (r * r);
    const double lit = scene.ambient + scene.diffuse * std::max(0.0, n.dot(to_light) / r) * falloff;
    return albedo * static_cast<float>(lit);
  };

  // Pass 1: the centre ray of every pixel (depth, incidence, which panel it sees).
  std::vector<Hit> hits(static_cast<std::size_t>(W) * H);
  for (int v = 0; v < H; ++v) {
    for (int u = 0; u < W; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * W + u;
      const Eigen::Vector3d ray((u - cam.cx) / cam.fx, (v - cam.cy) / cam.fy, 1.0);
      hits[i] = cast(panels, ray);
      out.true_depth[i] = static_cast<float>(hits[i].z);
      if (hits[i].panel >= 0) {
        cos_incidence[i] = static_cast<float>(std::fabs(panels[hits[i].panel].normal.dot(ray)) / ray.norm());
      }
    }
  }
  // Pass 2: colour. Textures are prefiltered (mip) over the pixel footprint, which
  // anti-aliases their interior; only pixels on a silhouette or panel seam (a 4-neighbour
  // sees another panel) are supersampled ss x ss to anti-alias geometric edges.
  for (int v = 0; v < H; ++v) {
    for (int u = 0; u < W; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * W + u;
      const int id = hits[i].panel;
      const bool seam = (u > 0 && hits[i - 1].panel != id) || (u + 1 < W && hits[i + 1].panel != id) ||
                        (v > 0 && hits[i - W].panel != id) || (v + 1 < H && hits[i + W].panel != id);
      if (ss == 1 || !seam) {
        const Eigen::Vector3d ray((u - cam.cx) / cam.fx, (v - cam.cy) / cam.fy, 1.0);
        radiance[i] = shade(ray, hits[i], 1.0);
        continue;
      }
      Eigen::Vector3f acc = Eigen::Vector3f::Zero();
      for (int sy = 0; sy < ss; ++sy) {
        for (int sx = 0; sx < ss; ++sx) {
          const double du = (sx + 0.5) / ss - 0.5, dv = (sy + 0.5) / ss - 0.5;
          const Eigen::Vector3d sub((u + du - cam.cx) / cam.fx, (v + dv - cam.cy) / cam.fy, 1.0);
          acc += shade(sub, cast(panels, sub), 1.0 / ss);
        }
      }
      radiance[i] = acc / static_cast<float>(ss * ss);
    }
  }

  // Depth validity: range, incidence, then occluding edges (on the true depth) dilated.
  const DepthSensorModel& dm = settings.depth;
  const double min_cos = std::cos(dm.max_incidence_deg * M_PI / 180.0);
  std::vector<std::uint8_t> valid(static_cast<std::size_t>(W) * H, 0);
  for (std::size_t i = 0; i < valid.size(); ++i) {
    const double z = out.true_depth[i];
    valid[i] = z > 0 && z >= dm.min_range_m && z <= dm.max_range_m && cos_incidence[i] >= min_cos;
  }
  std::vector<std::uint8_t> edge(static_cast<std::size_t>(W) * H, 0);
  const auto jump = [&](std::size_t a, std::size_t b) {
    const float za = out.true_depth[a], zb = out.true_depth[b];
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
  for (int v = 0; v < H; ++v) {
    for (int u = 0; u < W; ++u) {
      if (!edge[static_cast<std::size_t>(v) * W + u]) continue;
      for (int y = std::max(0, v - band); y <= std::min(H - 1, v + band); ++y) {
        for (int x = std::max(0, u - band); x <= std::min(W - 1, u + band); ++x) valid[static_cast<std::size_t>(y) * W + x] = 0;
      }
    }
  }

  const double fb = dm.ir_focal_px * dm.baseline_m;
  const std::uint64_t depth_key = hash3(settings.noise_seed, kDepthStream, frame_index);
  const std::vector<float> depth_noise =
      settings.sensor_noise ? correlated_normal_field(depth_key, W, H, dm.noise_correlation_px) : std::vector<float>();
  std::size_t n_valid = 0;
  for (std::size_t i = 0; i < valid.size(); ++i) {
    if (!valid[i]) continue;
    double z = out.true_depth[i];
    if (settings.sensor_noise) {
      z += dm.noise_coeff * z * z * depth_noise[i];
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
  const double scale = im.full_scale * out.exposure_gain;
  const std::uint64_t intensity_key = hash3(settings.noise_seed, kIntensityStream, frame_index);
  const float read2 = static_cast<float>(im.read_noise * im.read_noise);
  const float shot = static_cast<float>(im.shot_noise_gain);
  for (std::size_t i = 0; i < radiance.size(); ++i) {
    float value[3];
    for (int c = 0; c < 3; ++c) value[c] = static_cast<float>(scale) * radiance[i][c];
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
