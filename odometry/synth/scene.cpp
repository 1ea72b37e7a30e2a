#include "odometry/synth/scene.h"

#include <cmath>

#include "odometry/synth/random.h"
#include "solvers/error.h"

namespace bivo::odometry::synth {

std::string SynthCategory::name() const {
  return std::string(structure ? "structure" : "nostructure") + (texture ? "_texture" : "_notexture") +
         (near ? "_near" : "_far");
}

SynthCategory parse_category(const std::string& category, const std::string& distance) {
  SynthCategory c;
  std::string rest = category;
  const auto take = [&rest](const std::string& prefix) {
    if (rest.rfind(prefix, 0) == 0) {
      rest = rest.substr(prefix.size());
      return true;
    }
    return false;
  };
  const auto fail = [&]() {
    return Error("unknown synthetic category '" + category +
                 "': expected {structure|nostructure}_{texture|notexture}[_{near|far}], "
                 "e.g. structure_texture_near");
  };
  if (take("nostructure"))
    c.structure = false;
  else if (take("structure"))
    c.structure = true;
  else
    throw fail();
  if (take("_notexture"))
    c.texture = false;
  else if (take("_texture"))
    c.texture = true;
  else
    throw fail();
  std::string dist;
  if (rest == "_near" || rest == "_far")
    dist = rest.substr(1);
  else if (!rest.empty())
    throw fail();
  if (!distance.empty()) {
    if (distance != "near" && distance != "far") {
      throw Error("unknown distance '" + distance + "': expected near or far");
    }
    if (!dist.empty() && dist != distance) {
      throw Error("category '" + category + "' contradicts distance '" + distance + "'");
    }
    dist = distance;
  }
  if (dist.empty()) {
    throw Error("category '" + category + "' needs a distance: append _near/_far or give near|far");
  }
  c.near = dist == "near";
  return c;
}

std::vector<SynthCategory> all_categories() {
  std::vector<SynthCategory> out;
  for (bool near : {true, false}) {
    // Paper's column order: (structure, texture) = (no, yes), (yes, no), (no, no), (yes, yes).
    for (auto st : {std::pair{false, true}, {true, false}, {false, false}, {true, true}}) {
      SynthCategory c;
      c.structure = st.first;
      c.texture = st.second;
      c.near = near;
      out.push_back(c);
    }
  }
  return out;
}

Eigen::Isometry3d look_at(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - eye).normalized();
  Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ());
  if (x.norm() < 1e-9) throw Error("look_at: viewing direction is vertical, image 'up' undefined");
  x.normalize();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear().col(0) = x;
  T.linear().col(1) = y;
  T.linear().col(2) = z;
  T.translation() = eye;
  return T;
}

namespace {

Panel rectangle(const std::string& name, const Eigen::Vector3d& origin, const Eigen::Vector3d& u,
                const Eigen::Vector3d& v, int material) {
  Panel p{name, origin, u, v, material};
  return p;
}

}  // namespace

Scene build_scene(const SynthCategory& category, std::uint64_t seed, const SceneLayout& layout) {
  if (!(layout.wall_behind_m > 0.1 && layout.wall_behind_m <= 20.0) ||
      !(layout.distance_m == 0.0 || (layout.distance_m > 0.1 && layout.distance_m <= 20.0)) ||
      !(layout.pitch_deg >= 0.0 && layout.pitch_deg <= 89.0)) {
    throw Error("scene layout: wall distance " + std::to_string(layout.wall_behind_m) + " m and camera distance " +
                std::to_string(layout.distance_m) + " m must be in (0.1, 20] m (distance 0 = the category's), pitch " +
                std::to_string(layout.pitch_deg) + " deg in [0, 89]");
  }
  Scene s;
  s.category = category;
  s.seed = seed;
  constexpr int kPosters = 8;
  constexpr double kHalfLength = 6.0;  // the scene extends 12 m along x: room for sideways motion

  // Textures 0..7 posters (texture categories only), then foil, floor, wall.
  if (category.texture) {
    for (int i = 0; i < kPosters; ++i) s.textures.push_back(make_poster_texture(hash3(seed, 0x70, i)));
  }
  const int foil = static_cast<int>(s.textures.size());
  s.textures.push_back(make_uniform_texture(hash3(seed, 0x66, 0), {0.86f, 0.86f, 0.84f}, 0.01f));
  const int floor_tex = foil + 1;
  s.textures.push_back(make_uniform_texture(hash3(seed, 0x66, 1), {0.42f, 0.42f, 0.44f}, 0.01f));
  const int wall_tex = foil + 2;
  s.textures.push_back(make_uniform_texture(hash3(seed, 0x66, 2), {0.70f, 0.68f, 0.64f}, 0.01f));

  Material cover;
  if (category.texture) {
    cover.name = "posters";
    for (int i = 0; i < kPosters; ++i) cover.textures.push_back(i);
    cover.tile_u_m = 0.5;
    cover.tile_v_m = 0.5;
  } else {
    cover.name = "white_foil";
    cover.textures = {foil};
    cover.tile_u_m = cover.tile_v_m = 2.0;
  }
  s.materials.push_back(cover);
  s.materials.push_back(Material{"floor", {floor_tex}, 2.0, 2.0});
  s.materials.push_back(Material{"wall", {wall_tex}, 2.0, 2.0});

  const Eigen::Vector3d along(2 * kHalfLength, 0, 0);
  const double d = layout.distance_m > 0 ? layout.distance_m : category.distance_m();
  // Nominal view: looking straight at the scene (along +y), pitched down as the real fr3
  // recordings are (their optical axes meet the floor 1.36 / 2.16 m in front of the camera
  // at heights 0.88 / 1.09 m, structure near / far; nostructure_texture_near_withloop:
  // 55 degrees at 1.07 m).
  double pitch_deg = 55.0;
  if (category.structure) {
    // Zig-zag profile in the (x, y) plane: vertical fold lines every kFoldPitch along x,
    // alternating between y = 0 (towards the camera) and y = kFoldDepth; 1 m high.
    constexpr double kFoldPitch = 0.5, kFoldDepth = 0.4, kHeight = 1.0;
    const double kWallY = kFoldDepth + layout.wall_behind_m;
    const int n = static_cast<int>(std::lround(2 * kHalfLength / kFoldPitch));
    for (int i = 0; i < n; ++i) {
      const Eigen::Vector3d a(-kHalfLength + i * kFoldPitch, i % 2 ? kFoldDepth : 0.0, 0.0);
      const Eigen::Vector3d b(-kHalfLength + (i + 1) * kFoldPitch, i % 2 ? 0.0 : kFoldDepth, 0.0);
      s.panels.push_back(rectangle("zigzag_" + std::to_string(i), a, b - a, {0, 0, kHeight}, 0));
    }
    // Floor in three strips (no overlaps): far in front, the strip in front of and under
    // the zig-zag (posters in the texture categories, as on the real floor), behind it.
    constexpr double kStripFront = -2.5;
    s.panels.push_back(rectangle("floor", {-kHalfLength, -6.0, 0.0}, along, {0, kStripFront + 6.0, 0}, 1));
    s.panels.push_back(rectangle("floor_strip", {-kHalfLength, kStripFront, 0.0}, along,
                                 {0, kFoldDepth - kStripFront, 0}, category.texture ? 0 : 1));
    s.panels.push_back(rectangle("floor_back", {-kHalfLength, kFoldDepth, 0.0}, along, {0, kWallY - kFoldDepth, 0}, 1));
    s.panels.push_back(rectangle("wall", {-kHalfLength, kWallY, 0.0}, along, {0, 0, 3.0}, 2));
    // The optical axis meets the zig-zag's mid plane (y = kFoldDepth / 2) mid-panel, at the
    // height that puts the camera at the real one: low, so floor and panels share the view.
    pitch_deg = layout.pitch_deg > 0 ? layout.pitch_deg : (category.near ? 31.0 : 27.0);
    const double camera_height = category.near ? 0.88 : 1.09;
    s.target =
        Eigen::Vector3d(0.5 * kFoldPitch, 0.5 * kFoldDepth, camera_height - d * std::sin(pitch_deg * M_PI / 180.0));
  } else {
    s.panels.push_back(rectangle("plane", {-kHalfLength, -4.0, 0.0}, along, {0, 16.0, 0}, 0));
    s.target = Eigen::Vector3d::Zero();
  }
  if (layout.pitch_deg > 0) pitch_deg = layout.pitch_deg;
  const double pitch = pitch_deg * M_PI / 180.0;
  const Eigen::Vector3d dir(0.0, std::cos(pitch), -std::sin(pitch));
  s.nominal_T_wc = look_at(s.target - d * dir, s.target);
  for (const auto& p : s.panels) {
    if (std::fabs(p.edge_u.dot(p.edge_v)) > 1e-9 * p.edge_u.norm() * p.edge_v.norm()) {
      throw Error("panel '" + p.name + "' is not a rectangle");
    }
  }
  // A ceiling lamp 3.5 m above the floor, in front of and left of the scene.
  s.light_position = s.target + Eigen::Vector3d(-1.0, -2.0, 3.5 - s.target.z());
  s.light_reference_m = (s.light_position - s.target).norm();
  return s;
}

}  // namespace bivo::odometry::synth
