#pragma once
// Rendering one frame whose colour rows and depth are taken at their own times on the
// trajectory (rolling shutter, motion blur, unsynchronized depth) and whose depth camera
// sits at its own pose (misregistration): the defects of defects.h that need the motion.
#include <cstdint>
#include <functional>

#include <Eigen/Geometry>

#include "odometry/synth/render.h"
#include "odometry/synth/scene.h"

namespace bivo::odometry::synth {

// Camera-to-world pose of the colour camera dt seconds after the frame's timestamp.
using PoseAtTime = std::function<Eigen::Isometry3d(double dt)>;

// Colour: every row the average of settings.defects' row_sample_times poses (one view per
// sample, each with one pose per row), so a known motion blurs exactly as the average of
// the images along it. Depth: one view at pose_at(depth_delay) * colour_to_depth, stored in
// the colour camera's pixel grid. Without timing or misregistration defects this is
// render_frame(scene, pose_at(0), settings, frame_index).
RenderedFrame render_timed_frame(const Scene& scene, const PoseAtTime& pose_at, const RenderSettings& settings,
                                 std::uint64_t frame_index);

}  // namespace bivo::odometry::synth
