#include "odometry/synth/render.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include "odometry/io/input_limits.h"
#include "odometry/synth/random.h"
#include "solvers/error.h"

namespace bivo::odometry::synth {

namespace {

// A scene rectangle expressed in the camera frame, with what the intersection test needs.
struct CameraPanel {
  Eigen::Vector3d origin, edge_u, edge_v, normal;
  double plane_offset;            // normal . origin
  double inv_len2_u, inv_len2_v;  // 1 / |edge|^2
  double len_u, len_v;
  int material;
  int id;             // index in the scene: rows of a rolling shutter see different lists
  std::uint64_t key;  // which poster each texture cell shows (scene seed, panel index)
};

struct Hit {
  int panel = -1;  // index in the pose's panel list
  int id = -1;     // index in the scene
  double z = 0.0;  // depth along the optical axis (the ray has unit z component)
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
    best.id = p.id;
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

// The scene as one camera pose sees it: the panels inside its frustum, in its frame.
struct PoseView {
  std::vector<CameraPanel> panels;
  Eigen::Vector3d light_c;
};

PoseView pose_view(const Scene& scene, const Eigen::Isometry3d& T_wc, const PinholeCamera& cam) {
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
    for (const Eigen::Vector3d& w :
         {p.origin, Eigen::Vector3d(p.origin + p.edge_u), Eigen::Vector3d(p.origin + p.edge_v),
          Eigen::Vector3d(p.origin + p.edge_u + p.edge_v)}) {
      const Eigen::Vector3d q = R_cw * w + t_cw;
      out[0] = out[0] && q.x() < kx0 * q.z();
      out[1] = out[1] && q.x() > kx1 * q.z();
      out[2] = out[2] && q.y() < ky0 * q.z();
      out[3] = out[3] && q.y() > ky1 * q.z();
    }
    return out[0] || out[1] || out[2] || out[3];
  };
  PoseView view;
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
    c.id = static_cast<int>(&p - scene.panels.data());
    c.key = hash3(scene.seed, 0xCE11, static_cast<std::uint64_t>(c.id));
    view.panels.push_back(c);
  }
  view.light_c = R_cw * scene.light_position + t_cw;
  return view;
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
  validate(s.defects);
}

SceneView view_scene(const Scene& scene, const std::vector<Eigen::Isometry3d>& row_poses,
                     const RenderSettings& settings, bool with_radiance) {
  const PinholeCamera& cam = settings.camera;
  validate(settings);
  if (row_poses.size() != 1 && row_poses.size() != static_cast<std::size_t>(cam.height)) {
    throw Error("render_frame: " + std::to_string(row_poses.size()) + " row poses for " + std::to_string(cam.height) +
                " rows (give 1 or one per row)");
  }
  const int W = cam.width, H = cam.height, ss = settings.supersampling;
  const double focal = std::sqrt(cam.fx * cam.fy);
  SceneView out;
  out.width = W;
  out.height = H;
  out.true_depth.assign(static_cast<std::size_t>(W) * H, 0.0f);
  out.cos_incidence.assign(static_cast<std::size_t>(W) * H, 0.0f);
  std::vector<PoseView> views;
  for (const Eigen::Isometry3d& T : row_poses) views.push_back(pose_view(scene, T, cam));
  const auto view_of_row = [&](int v) -> const PoseView& { return views[views.size() == 1 ? 0 : v]; };

  // Radiance (albedo x shading, before exposure) seen along one ray, with the texture
  // prefiltered over the sample's footprint of `footprint_px` pixels.
  const auto shade = [&](const PoseView& view, const Eigen::Vector3d& ray, const Hit& hit,
                         double footprint_px) -> Eigen::Vector3f {
    if (hit.panel < 0) return scene.background;
    const CameraPanel& p = view.panels[hit.panel];
    const Material& m = scene.materials[p.material];
    const double cos_inc = std::fabs(p.normal.dot(ray)) / ray.norm();
    const double u_m = hit.a * p.len_u, v_m = hit.b * p.len_v;
    const double cu = std::floor(u_m / m.tile_u_m), cv = std::floor(v_m / m.tile_v_m);
    const std::uint64_t cell = (static_cast<std::uint64_t>(cu) << 32) ^ static_cast<std::uint64_t>(cv);
    const int tex = m.textures.size() == 1 ? m.textures[0] : m.textures[mix64(p.key ^ cell) % m.textures.size()];
    const MipTexture& T = scene.textures[tex];
    // Footprint on the surface: z/f per pixel across the ray, stretched by 1/cos along
    // the slope; the geometric mean of the two makes an isotropic filter width.
    const double footprint_m = hit.z * footprint_px / focal / std::sqrt(std::max(cos_inc, 0.05));
    const float texels = static_cast<float>(footprint_m / m.tile_u_m * T.width());
    const Eigen::Vector3f albedo =
        T.sample(static_cast<float>(u_m / m.tile_u_m - cu), static_cast<float>(v_m / m.tile_v_m - cv), texels);
    const Eigen::Vector3d n = p.normal.dot(ray) > 0 ? Eigen::Vector3d(-p.normal) : p.normal;
    const Eigen::Vector3d to_light = view.light_c - hit.z * ray;  // rays have unit z: hit.z * ray is the point
    const double r = to_light.norm();
    const double falloff = scene.light_reference_m * scene.light_reference_m / (r * r);
    const double lit = scene.ambient + scene.diffuse * std::max(0.0, n.dot(to_light) / r) * falloff;
    return albedo * static_cast<float>(lit);
  };

  // Pass 1: the centre ray of every pixel (depth, incidence, which panel it sees).
  std::vector<Hit> hits(static_cast<std::size_t>(W) * H);
  for (int v = 0; v < H; ++v) {
    const std::vector<CameraPanel>& panels = view_of_row(v).panels;
    for (int u = 0; u < W; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * W + u;
      const Eigen::Vector3d ray((u - cam.cx) / cam.fx, (v - cam.cy) / cam.fy, 1.0);
      hits[i] = cast(panels, ray);
      out.true_depth[i] = static_cast<float>(hits[i].z);
      if (hits[i].panel >= 0) {
        out.cos_incidence[i] = static_cast<float>(std::fabs(panels[hits[i].panel].normal.dot(ray)) / ray.norm());
      }
    }
  }
  if (!with_radiance) return out;
  out.radiance.resize(static_cast<std::size_t>(W) * H);
  // Pass 2: colour. Textures are prefiltered (mip) over the pixel footprint, which
  // anti-aliases their interior; only pixels on a silhouette or panel seam (a 4-neighbour
  // sees another panel) are supersampled ss x ss to anti-alias geometric edges.
  for (int v = 0; v < H; ++v) {
    const PoseView& view = view_of_row(v);
    for (int u = 0; u < W; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * W + u;
      const int id = hits[i].id;
      const bool seam = (u > 0 && hits[i - 1].id != id) || (u + 1 < W && hits[i + 1].id != id) ||
                        (v > 0 && hits[i - W].id != id) || (v + 1 < H && hits[i + W].id != id);
      if (ss == 1 || !seam) {
        const Eigen::Vector3d ray((u - cam.cx) / cam.fx, (v - cam.cy) / cam.fy, 1.0);
        out.radiance[i] = shade(view, ray, hits[i], 1.0);
        continue;
      }
      Eigen::Vector3f acc = Eigen::Vector3f::Zero();
      for (int sy = 0; sy < ss; ++sy) {
        for (int sx = 0; sx < ss; ++sx) {
          const double du = (sx + 0.5) / ss - 0.5, dv = (sy + 0.5) / ss - 0.5;
          const Eigen::Vector3d sub((u + du - cam.cx) / cam.fx, (v + dv - cam.cy) / cam.fy, 1.0);
          acc += shade(view, sub, cast(view.panels, sub), 1.0 / ss);
        }
      }
      out.radiance[i] = acc / static_cast<float>(ss * ss);
    }
  }
  return out;
}

RenderedFrame render_frame(const Scene& scene, const Eigen::Isometry3d& T_wc, const RenderSettings& settings,
                           std::uint64_t frame_index) {
  const SceneView view = view_scene(scene, {T_wc}, settings, true);
  return sense(view, view, settings, frame_index);
}

}  // namespace bivo::odometry::synth
