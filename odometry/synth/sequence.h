#pragma once
// Synthetic TUM-format RGB-D sequences with exact ground truth ("Structure vs. Texture").
//
// Usage (from `bivo demo` or a test):
//
//   namespace synth = bivo::odometry::synth;
//   synth::SynthOptions o;
//   o.category = synth::parse_category("structure_texture_near");
//   o.frames = 90;
//   o.seed = 7;
//   // generated hand-held motion (no data needed) ...
//   std::string seq = synth::render_sequence(o, "out/synth");
//   // ... or real motion:  render_sequence(o, io::read_tum_trajectory(path), "out/synth", path)
//   // seq == "out/synth/rgbd_dataset_freiburg3_synth_structure_texture_near": a TUM folder
//   // (rgb/, depth/, rgb.txt, depth.txt, associations.txt, groundtruth.txt, scene.json)
//   // whose name makes the intrinsics preset pick freiburg3.
//
// The folder is rendered into a temporary folder beside it and renamed when complete
// (io::StagedFolder), so a failed run leaves no half-written sequence. An existing folder of
// the same name is never replaced, unless replace_own_folder is set and it is one that a
// previous rendering wrote (its io::kOutputMarker file).
#include <cstdint>
#include <string>

#include "odometry/io/trajectory.h"
#include "odometry/synth/motion.h"
#include "odometry/synth/render.h"
#include "odometry/synth/scene.h"

namespace bivo::odometry::synth {

struct SynthOptions {
  SynthCategory category;
  int frames = 90;
  std::uint64_t seed = 1;  // scene textures, sensor noise and generated motion
  double fps = 30.0;
  // Frames start this long after the first pose of the motion.
  double start_offset_s = 0.0;
  // Which frame of the sequence is re-anchored to the scene's nominal viewing pose:
  // -1 = the middle frame (keeps the scene in view best over the whole sequence).
  int anchor_frame = -1;
  // Fast motion: the trajectory is played time_scale times faster (frame k shows the pose
  // at start + time_scale * k / fps seconds of the original recording's clock).
  double time_scale = 1.0;
  SceneLayout layout;     // scene variant (far background); defaults = the benchmark's scenes
  RenderSettings render;  // camera (freiburg3 defaults), sensor models, supersampling
  // Generated motion when none is given; its seed is overwritten by `seed`.
  HandheldMotionOptions handheld;
  // Frames are rendered and written by this many threads (0 = one per hardware thread);
  // the files do not depend on it (all randomness is per frame).
  int threads = 0;
  // Folder name; empty = "rgbd_dataset_freiburg3_synth_<category>". Must make
  // io::intrinsics_for_sequence() pick the rendering camera (contain "freiburg3" and no other
  // preset name such as "freiburg1").
  std::string sequence_name;
  // Replace an existing output folder when bivo wrote it (never a user's folder or a symlink).
  bool replace_own_folder = false;
};

std::string default_sequence_name(const SynthCategory& category);

// Renders options.frames frames along `motion` (resampled at options.fps from its first
// pose + start_offset_s, re-anchored by one rigid transform so the scene is in view) into
// output_dir/<sequence name>; returns that path. `motion_source` is recorded in scene.json
// and named in errors.
std::string render_sequence(const SynthOptions& options, const io::Trajectory& motion, const std::string& output_dir,
                            const std::string& motion_source);

// Same along generated hand-held motion (options.handheld, seeded with options.seed).
std::string render_sequence(const SynthOptions& options, const std::string& output_dir);

// The frame poses a sequence is rendered with (resampled and re-anchored), exactly the
// poses written to groundtruth.txt; `anchor` (optional) receives the re-anchoring transform.
io::Trajectory frame_poses(const SynthOptions& options, const Scene& scene, const io::Trajectory& motion,
                           const std::string& motion_source, Eigen::Isometry3d* anchor = nullptr);

}  // namespace bivo::odometry::synth
