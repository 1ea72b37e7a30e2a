#pragma once
// Scenes of the synthetic "Structure vs. Texture" set (TUM freiburg3 look-alikes): planar
// textured rectangles, a point light, and the nominal camera pose from which the scene is
// viewed at the category's distance. Sizes and the nominal views follow the real fr3
// recordings (docs/synthetic.md, "Scenes").
//
//  * structure: a zig-zag of upright wooden panels standing on the floor, like a folding
//    screen: vertical fold lines every 0.5 m along x, alternating between y = 0 and
//    y = 0.4 m (panels 0.64 m wide, 1 m high, +-39 degrees to the zig-zag's line), 12 m
//    long, a wall 1.5 m behind it. The panels' two normals and the floor's span all three
//    directions, so depth alone constrains all six degrees of freedom;
//  * nostructure: one single plane (the floor), nothing else;
//  * texture: the panels (or the plane) and the floor strip in front of the zig-zag are
//    covered with colourful posters; notexture: the panels (or the plane) are covered with
//    near-uniform white foil (1% low-frequency albedo variation) and the strip is plain
//    floor. Texture twins are the same geometry, only the albedo differs;
//  * light: ambient plus a point light (a ceiling lamp) with inverse-square falloff, so
//    even white foil shows faint smooth shading and a step where panels fold;
//  * near / far: the nominal camera looks at the scene from the distances, heights and
//    pitch angles of the real fr3 recordings (structure: 31 / 27 degrees down at 1.4 /
//    2.25 m, both panels and floor in view; nostructure: 55 degrees down at 1.4 / 2.25 m).
// World frame: z up, the zig-zag runs along x, the nominal camera looks along +y.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "odometry/synth/texture.h"

namespace bivo::odometry::synth {

struct SynthCategory {
  bool structure = true;
  bool texture = true;
  bool near = true;
  // e.g. "structure_texture_near", "nostructure_notexture_far".
  std::string name() const;
  // Nominal camera-to-target distance along the optical axis: 1.4 m near, 2.25 m far
  // (the real fr3 structure recordings: 1.2 m / 2 m horizontally from the zig-zag).
  double distance_m() const { return near ? 1.4 : 2.25; }
};

// Accepts "structure_texture_near" (distance included; `distance` must then be empty or
// agree) or "structure_texture" with distance "near"/"far". Throws bivo::Error naming the
// value otherwise.
SynthCategory parse_category(const std::string& category, const std::string& distance = "");

// The 8 categories in the paper's table order (near first).
std::vector<SynthCategory> all_categories();

// Material: textures tiled over the surface in cells of tile_u x tile_v metres; each cell
// shows one of `textures` picked by a hash of (scene seed, panel, cell).
struct Material {
  std::string name;
  std::vector<int> textures;
  double tile_u_m = 1.0, tile_v_m = 1.0;
};

// Rectangle origin + a*edge_u + b*edge_v, a, b in [0, 1]; edge_u is perpendicular to edge_v.
struct Panel {
  std::string name;
  Eigen::Vector3d origin, edge_u, edge_v;
  int material = 0;
  Eigen::Vector3d normal() const { return edge_u.cross(edge_v).normalized(); }
};

struct Scene {
  SynthCategory category;
  std::uint64_t seed = 0;
  std::vector<Panel> panels;
  std::vector<Material> materials;
  std::vector<MipTexture> textures;
  // Lambertian shading under ambient light and one point light at light_position:
  //   radiance = albedo * (ambient + diffuse * max(0, n . l) * (light_reference_m / r)^2)
  // with l the unit direction and r the distance from the surface point to the light;
  // light_reference_m is the light's distance to `target` (there the falloff factor is 1).
  Eigen::Vector3d light_position = Eigen::Vector3d(0, 0, 3);
  double light_reference_m = 3.0;
  double ambient = 0.55, diffuse = 0.45;
  Eigen::Vector3f background = Eigen::Vector3f::Constant(0.3f);  // albedo-like, rays that miss
  Eigen::Isometry3d nominal_T_wc = Eigen::Isometry3d::Identity();
  Eigen::Vector3d target = Eigen::Vector3d::Zero();  // the point the nominal camera looks at
};

// Variants of a category's geometry and nominal view; the defaults are the benchmark's
// scenes. Far background: a wall farther back and a camera farther away put much of the
// image beyond 3 m, as in real office recordings (docs/synthetic.md, "Sensor defects").
struct SceneLayout {
  double wall_behind_m = 1.5;  // structure: the wall's distance behind the zig-zag's back folds
  double distance_m = 0.0;     // nominal camera-to-target distance; 0 = category.distance_m()
  double pitch_deg = 0.0;      // nominal view's downward pitch; 0 = the category's
};

// Builds the scene of `category`; textures are generated from `seed`. Throws bivo::Error
// when a layout value is outside (0.1, 20] m (0 keeps the distance) or the pitch outside
// [0, 89] degrees (0 keeps the category's).
Scene build_scene(const SynthCategory& category, std::uint64_t seed, const SceneLayout& layout = {});

// Camera pose at `eye` looking at `target` with image "up" towards world +z
// (camera axes: x right, y down, z forward).
Eigen::Isometry3d look_at(const Eigen::Vector3d& eye, const Eigen::Vector3d& target);

}  // namespace bivo::odometry::synth
