#include "odometry/synth/exposure.h"

#include <vector>

#include "odometry/synth/defects.h"

namespace bivo::odometry::synth {

RenderedFrame render_timed_frame(const Scene& scene, const PoseAtTime& pose_at, const RenderSettings& settings,
                                 std::uint64_t frame_index) {
  validate(settings);
  const SensorDefects& d = settings.defects;
  const int H = settings.camera.height;
  SceneView colour;
  if (!d.timed_colour()) {
    colour = view_scene(scene, {pose_at(0.0)}, settings, true);
  } else {
    std::vector<std::vector<double>> times(H);
    for (int v = 0; v < H; ++v) times[v] = row_sample_times(d, v, H);
    const std::size_t samples = times[0].size();
    std::vector<Eigen::Isometry3d> rows(H);
    for (std::size_t j = 0; j < samples; ++j) {
      for (int v = 0; v < H; ++v) rows[v] = pose_at(times[v][j]);
      SceneView s = view_scene(scene, rows, settings, true);
      if (j == 0) {
        colour = std::move(s);
        continue;
      }
      for (std::size_t i = 0; i < colour.radiance.size(); ++i) colour.radiance[i] += s.radiance[i];
    }
    // Box filter over the exposure: the mean radiance of the samples.
    for (Eigen::Vector3f& r : colour.radiance) r /= static_cast<float>(samples);
  }
  const double delay = depth_delay(d, settings.noise_seed, frame_index);
  if (!d.timed_colour() && !d.misregistered() && delay == 0.0) return sense(colour, colour, settings, frame_index);
  const SceneView depth = view_scene(scene, {pose_at(delay) * colour_to_depth(d)}, settings, false);
  return sense(depth, colour, settings, frame_index);
}

}  // namespace bivo::odometry::synth
