#pragma once
// Scenes of the synthetic "Structure vs. Texture" set (TUM freiburg3 look-alikes): planar
// textured rectangles, a directional light, and the nominal camera pose from which the
// scene is viewed at the category's distance.
//
//  * structure: an upright zig-zag of four wooden panels (horizontal fold lines every
//    0.3 m of height, 0.3 m fold depth, 1.2 m high, 12 m long) standing on a floor, with
//    a wall 1.5 m behind it;
//  * nostructure: one single plane (the floor), viewed obliquely (50 degrees down);
//  * texture: the zig-zag panels (or the plane) are covered with colourful posters;
//  * notexture: they are covered with near-uniform white foil (1% low-frequency albedo
//    variation); floor and wall are near-uniform in every category;
//  * near / far: the camera looks at the scene from 1 m / 2 m along its optical axis
//    (structure: 15 degrees down, 25 degrees sideways; nostructure: 50 degrees down).
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
  // Nominal camera-to-target distance along the optical axis: 1 m near, 2 m far.
  double distance_m() const { return near ? 1.0 : 2.0; }
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
  // Lambertian shading: radiance = albedo * (ambient + diffuse * max(0, n . light)).
  Eigen::Vector3d light_direction = Eigen::Vector3d::UnitZ();  // unit, towards the light
  double ambient = 0.4, diffuse = 0.6;
  Eigen::Vector3f background = Eigen::Vector3f::Constant(0.3f);  // albedo-like, rays that miss
  Eigen::Isometry3d nominal_T_wc = Eigen::Isometry3d::Identity();
  Eigen::Vector3d target = Eigen::Vector3d::Zero();  // the point the nominal camera looks at
};

// Builds the scene of `category`; textures are generated from `seed`.
Scene build_scene(const SynthCategory& category, std::uint64_t seed);

// Camera pose at `eye` looking at `target` with image "up" towards world +z
// (camera axes: x right, y down, z forward).
Eigen::Isometry3d look_at(const Eigen::Vector3d& eye, const Eigen::Vector3d& target);

}  // namespace bivo::odometry::synth
