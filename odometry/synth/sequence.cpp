#include "odometry/synth/sequence.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iomanip>
#include <sstream>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "odometry/io/atomic_file.h"
#include "odometry/io/camera_intrinsics.h"
#include "odometry/io/input_limits.h"
#include "odometry/io/png_io.h"
#include "odometry/io/pose_error.h"
#include "odometry/io/staged_folder.h"
#include "odometry/synth/exposure.h"
#include "solvers/error.h"

namespace bivo::odometry::synth {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string stamp(double t) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6f", t);
  return buf;
}

json vec(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }

json pose_json(const Eigen::Isometry3d& T) {
  Eigen::Quaterniond q(T.linear());
  q.normalize();
  return json{{"t_xyz", vec(T.translation())}, {"q_xyzw", json::array({q.x(), q.y(), q.z(), q.w()})}};
}

json scene_json(const SynthOptions& o, const Scene& scene, const std::string& motion_source,
                const Eigen::Isometry3d& anchor, int anchor_frame, const io::Trajectory& poses,
                const std::vector<RenderedFrame>& stats, const std::vector<double>& depth_delays) {
  const RenderSettings& r = o.render;
  json panels = json::array();
  for (const Panel& p : scene.panels) {
    panels.push_back({{"name", p.name},
                      {"corners", json::array({vec(p.origin), vec(p.origin + p.edge_u),
                                               vec(p.origin + p.edge_u + p.edge_v), vec(p.origin + p.edge_v)})},
                      {"normal", vec(p.normal())},
                      {"material", scene.materials[p.material].name}});
  }
  json materials = json::array();
  for (const Material& m : scene.materials) {
    materials.push_back(
        {{"name", m.name}, {"tile_m", json::array({m.tile_u_m, m.tile_v_m})}, {"texture_count", m.textures.size()}});
  }
  double vmin = 1, vmax = 0, vsum = 0;
  json gains = json::array();
  for (const RenderedFrame& f : stats) {
    vmin = std::min(vmin, f.valid_depth_fraction);
    vmax = std::max(vmax, f.valid_depth_fraction);
    vsum += f.valid_depth_fraction;
    gains.push_back(f.exposure_gain);
  }
  const MotionSpeeds speeds = mean_speeds(poses);
  json out = json{
      {"generator", "bivo synth"},
      {"category", o.category.name()},
      {"structure", o.category.structure},
      {"texture", o.category.texture},
      {"distance_m", o.category.distance_m()},
      {"seed", o.seed},
      {"frames", o.frames},
      {"fps", o.fps},
      {"camera",
       {{"width", r.camera.width},
        {"height", r.camera.height},
        {"fx", r.camera.fx},
        {"fy", r.camera.fy},
        {"cx", r.camera.cx},
        {"cy", r.camera.cy}}},
      {"depth_sensor",
       {{"noise_coeff", r.depth.noise_coeff},
        {"noise_correlation_px", r.depth.noise_correlation_px},
        {"baseline_m", r.depth.baseline_m},
        {"ir_focal_px", r.depth.ir_focal_px},
        {"disparity_step_px", r.depth.disparity_step_px},
        {"min_range_m", r.depth.min_range_m},
        {"max_range_m", r.depth.max_range_m},
        {"max_incidence_deg", r.depth.max_incidence_deg},
        {"occlusion_jump_rel", r.depth.occlusion_jump_rel},
        {"occlusion_band_px", r.depth.occlusion_band_px},
        {"png_units_per_m", 5000}}},
      {"intensity_sensor",
       {{"read_noise", r.intensity.read_noise},
        {"shot_noise_gain", r.intensity.shot_noise_gain},
        {"exposure_jitter", r.intensity.exposure_jitter},
        {"full_scale", r.intensity.full_scale}}},
      {"sensor_noise", r.sensor_noise},
      {"supersampling", r.supersampling},
      {"motion",
       {{"source", motion_source},
        {"start_offset_s", o.start_offset_s},
        {"anchor_frame", anchor_frame},
        {"anchor_transform", pose_json(anchor)},
        {"mean_linear_speed_mps", speeds.linear_mps},
        {"mean_angular_speed_dps", speeds.angular_rps * 180.0 / M_PI}}},
      {"scene",
       {{"panels", panels},
        {"materials", materials},
        {"light_position", vec(scene.light_position)},
        {"light_reference_m", scene.light_reference_m},
        {"ambient", scene.ambient},
        {"diffuse", scene.diffuse},
        {"nominal_T_wc", pose_json(scene.nominal_T_wc)},
        {"target", vec(scene.target)}}},
      {"stats",
       {{"valid_depth_fraction_min", vmin},
        {"valid_depth_fraction_mean", stats.empty() ? 0.0 : vsum / stats.size()},
        {"valid_depth_fraction_max", vmax},
        {"exposure_gains", gains}}},
  };
  // Written only when used, so renderings without them keep their bytes.
  if (o.time_scale != 1.0) out["motion"]["time_scale"] = o.time_scale;
  const SceneLayout default_layout;
  if (o.layout.wall_behind_m != default_layout.wall_behind_m || o.layout.distance_m != default_layout.distance_m ||
      o.layout.pitch_deg != default_layout.pitch_deg) {
    out["scene"]["layout"] = {{"wall_behind_m", o.layout.wall_behind_m},
                              {"distance_m", o.layout.distance_m},
                              {"pitch_deg", o.layout.pitch_deg}};
  }
  const SensorDefects& d = r.defects;
  if (d.any()) {
    out["sensor_defects"] = {{"bias_radial", d.bias_radial},
                             {"static_noise_share", d.static_noise_share},
                             {"bias_lowfreq", d.bias_lowfreq},
                             {"bias_wavelength_px", d.bias_wavelength_px},
                             {"depth_offset_m", vec(d.depth_offset_m)},
                             {"depth_rotation_rad", vec(d.depth_rotation_rad)},
                             {"depth_delay_s", json::array({d.depth_delay_min_s, d.depth_delay_max_s})},
                             {"depth_delay_step_s", d.depth_delay_step_s},
                             {"readout_s", d.readout_s},
                             {"exposure_s", d.exposure_s},
                             {"blur_samples", d.blur_samples},
                             {"gain_step", d.gain_step},
                             {"gain_memory", d.gain_memory},
                             {"vignetting", d.vignetting}};
    // Only when on, so stress-set renderings made before these existed keep their bytes.
    if (d.noise_exponent != 2.0) out["sensor_defects"]["noise_exponent"] = d.noise_exponent;
    if (d.disparity_offset_step_px > 0) {
      out["sensor_defects"]["disparity_offset_step_px"] = d.disparity_offset_step_px;
      out["sensor_defects"]["disparity_offset_memory"] = d.disparity_offset_memory;
    }
    if (d.speckle_outliers > 0) out["sensor_defects"]["speckle_outliers"] = d.speckle_outliers;
    if (d.flying_pixels > 0) out["sensor_defects"]["flying_pixels"] = d.flying_pixels;
    out["stats"]["depth_delays_s"] = depth_delays;
  }
  return out;
}

// Every option is checked before any work: motion generation, rendering or a file.
void validate(const SynthOptions& o) {
  if (o.frames < 1) throw Error("synth: --frames must be >= 1, got " + std::to_string(o.frames));
  // A sequence whose lists its own reader would refuse is useless.
  io::check_list_size(o.frames, "synth: --frames " + std::to_string(o.frames));
  // Frame files are named by their timestamps at 1e-6 s: faster frames would share names.
  if (!(o.fps > 0 && o.fps <= 1e6)) {
    std::ostringstream m;
    m << "synth: --fps must be in (0, 1e6] (timestamps have 1e-6 s resolution), got " << o.fps;
    throw Error(m.str());
  }
  if (!(o.start_offset_s >= 0 && std::isfinite(o.start_offset_s))) {
    std::ostringstream m;
    m << "synth: --start must be a finite number of seconds >= 0, got " << o.start_offset_s;
    throw Error(m.str());
  }
  if (o.threads < 0 || o.threads > 256) {
    throw Error("synth: --threads must be in 0..256, got " + std::to_string(o.threads));
  }
  if (!(o.time_scale > 0 && o.time_scale <= 100)) {
    throw Error("synth: --time-scale must be in (0, 100], got " + std::to_string(o.time_scale));
  }
  // Nearest-timestamp association must pair each depth image with its own colour image.
  const SensorDefects& d = o.render.defects;
  if (!(std::fabs(d.depth_delay_min_s) < 0.5 / o.fps && std::fabs(d.depth_delay_max_s) < 0.5 / o.fps)) {
    std::ostringstream m;
    m << "synth: depth delays [" << d.depth_delay_min_s << ", " << d.depth_delay_max_s
      << "] s must stay within half a frame (" << 0.5 / o.fps << " s)";
    throw Error(m.str());
  }
  try {
    synth::validate(o.render);
  } catch (const Error& e) {
    throw Error(std::string("synth: ") + e.what());
  }
  const std::string name = o.sequence_name.empty() ? default_sequence_name(o.category) : o.sequence_name;
  // Readers pick intrinsics from the sequence name: it must select the rendering camera.
  const io::Intrinsics preset = io::intrinsics_for_sequence(name);
  const PinholeCamera& cam = o.render.camera;
  if (preset.fx != cam.fx || preset.fy != cam.fy || preset.cx != cam.cx || preset.cy != cam.cy) {
    throw Error("synth: sequence name '" + name + "' selects intrinsics " + std::to_string(preset.fx) + " " +
                std::to_string(preset.fy) + " " + std::to_string(preset.cx) + " " + std::to_string(preset.cy) +
                ", not the rendering camera's (freiburg3: name it with 'freiburg3' and no other preset)");
  }
  if (name.find('/') != std::string::npos || name == "." || name == "..") {
    throw Error("synth: sequence name '" + name + "' must be a plain folder name");
  }
  if (o.anchor_frame < -1 || o.anchor_frame >= o.frames) {
    throw Error("synth: anchor frame " + std::to_string(o.anchor_frame) + " is outside 0.." +
                std::to_string(o.frames - 1));
  }
}

}  // namespace

std::string default_sequence_name(const SynthCategory& category) {
  return "rgbd_dataset_freiburg3_synth_" + category.name();
}

io::Trajectory frame_poses(const SynthOptions& o, const Scene& scene, const io::Trajectory& motion,
                           const std::string& motion_source, Eigen::Isometry3d* anchor) {
  validate(o);
  io::Trajectory poses =
      resample_trajectory(retime_trajectory(motion, o.time_scale), o.start_offset_s, o.frames, o.fps, motion_source);
  const int ref = o.anchor_frame < 0 ? o.frames / 2 : o.anchor_frame;
  const Eigen::Isometry3d A = anchor_transform(poses[ref].T_wc, scene.nominal_T_wc);
  for (auto& p : poses) p.T_wc = A * p.T_wc;
  if (anchor) *anchor = A;
  return poses;
}

std::string render_sequence(const SynthOptions& o, const io::Trajectory& motion, const std::string& output_dir,
                            const std::string& motion_source) {
  validate(o);
  const std::string name = o.sequence_name.empty() ? default_sequence_name(o.category) : o.sequence_name;
  const Scene scene = build_scene(o.category, o.seed, o.layout);
  Eigen::Isometry3d anchor;
  const io::Trajectory planned = frame_poses(o, scene, motion, motion_source, &anchor);
  const int ref = o.anchor_frame < 0 ? o.frames / 2 : o.anchor_frame;
  // Timestamps name the frame files and are written with 1e-6 s resolution: two frames
  // with one stamp would overwrite each other's images (and make the lists invalid).
  for (int k = 1; k < o.frames; ++k) {
    if (stamp(planned[k].timestamp) == stamp(planned[k - 1].timestamp)) {
      throw Error("synth: frames " + std::to_string(k - 1) + " and " + std::to_string(k) + " both have timestamp " +
                  stamp(planned[k].timestamp) + " (1e-6 s resolution): lower --fps or --start");
    }
  }

  const fs::path final_dir = fs::path(output_dir) / name;
  io::StagedFolder staged = [&] {
    try {
      return io::StagedFolder(final_dir.string(), "bivo synth", o.replace_own_folder);
    } catch (const Error& e) {
      throw Error(std::string("synth: ") + e.what());
    }
  }();
  const fs::path tmp_dir = staged.path();
  try {
    fs::create_directories(tmp_dir / "rgb");
    fs::create_directories(tmp_dir / "depth");
    // Ground truth goes through the file first: the renderer then uses exactly the poses
    // a reader of groundtruth.txt gets (io::write_tum_trajectory rounds to 1e-9).
    const std::string gt_path = (tmp_dir / "groundtruth.txt").string();
    io::write_tum_trajectory(gt_path, planned);
    const io::Trajectory poses = io::read_tum_trajectory(gt_path);

    RenderSettings settings = o.render;
    settings.noise_seed = o.seed;
    std::vector<RenderedFrame> stats(o.frames);
    std::vector<std::string> stamps(o.frames), depth_stamps(o.frames);
    std::vector<double> delays(o.frames);
    const SensorDefects& defects = settings.defects;
    const bool timed = defects.timed_colour() || defects.misregistered() || defects.unsynchronized();
    const io::Trajectory timeline = retime_trajectory(motion, o.time_scale);
    const double t_first = timeline.front().timestamp + o.start_offset_s;
    const auto render_and_write = [&](int k) {
      const auto k64 = static_cast<std::uint64_t>(k);
      // Sub-frame times interpolate the motion (times outside it hold its end pose).
      const PoseAtTime pose_at = [&](double dt) -> Eigen::Isometry3d {
        if (dt == 0.0) return poses[k].T_wc;
        const double t = std::clamp(t_first + k / o.fps + dt, timeline.front().timestamp, timeline.back().timestamp);
        const auto T = io::interpolate_pose(timeline, t, 0.1);
        if (!T) throw Error("synth: no pose of '" + motion_source + "' near t=" + std::to_string(t) + " (gap)");
        return anchor * *T;
      };
      RenderedFrame f =
          timed ? render_timed_frame(scene, pose_at, settings, k64) : render_frame(scene, poses[k].T_wc, settings, k64);
      stamps[k] = stamp(poses[k].timestamp);
      delays[k] = depth_delay(defects, settings.noise_seed, k64);
      depth_stamps[k] = stamp(poses[k].timestamp + delays[k]);
      io::Png8 rgb;
      rgb.width = f.width;
      rgb.height = f.height;
      rgb.channels = 3;
      rgb.data = std::move(f.rgb);
      io::write_png8((tmp_dir / ("rgb/" + stamps[k] + ".png")).string(), rgb);
      io::Png16 depth;
      depth.width = f.width;
      depth.height = f.height;
      depth.data = std::move(f.depth);
      io::write_png16((tmp_dir / ("depth/" + depth_stamps[k] + ".png")).string(), depth);
      f.true_depth.clear();
      stats[k] = std::move(f);
    };
    // Frames are independent: worker w takes frames w, w + n, w + 2n, ...
    const int n_threads =
        std::clamp(o.threads > 0 ? o.threads : static_cast<int>(std::thread::hardware_concurrency()), 1, o.frames);
    std::vector<std::exception_ptr> failures(n_threads);
    std::vector<std::thread> workers;
    for (int w = 0; w < n_threads; ++w) {
      workers.emplace_back([&, w] {
        try {
          for (int k = w; k < o.frames; k += n_threads) render_and_write(k);
        } catch (...) {
          failures[w] = std::current_exception();
        }
      });
    }
    for (auto& t : workers) t.join();
    for (const auto& e : failures) {
      if (e) std::rethrow_exception(e);
    }
    std::ostringstream rgb_list, depth_list, assoc;
    rgb_list << "# color images\n# synthetic: " << name << "\n# timestamp filename\n";
    depth_list << "# depth maps\n# synthetic: " << name << "\n# timestamp filename\n";
    for (int k = 0; k < o.frames; ++k) {
      const std::string rgb_rel = "rgb/" + stamps[k] + ".png", depth_rel = "depth/" + depth_stamps[k] + ".png";
      rgb_list << stamps[k] << ' ' << rgb_rel << '\n';
      depth_list << depth_stamps[k] << ' ' << depth_rel << '\n';
      assoc << stamps[k] << ' ' << rgb_rel << ' ' << depth_stamps[k] << ' ' << depth_rel << '\n';
    }
    const auto write_text = [&](const char* file, const std::string& text) {
      io::write_file_atomically((tmp_dir / file).string(), [&](std::ostream& out) { out << text; });
    };
    write_text("rgb.txt", rgb_list.str());
    write_text("depth.txt", depth_list.str());
    write_text("associations.txt", assoc.str());
    write_text("scene.json", scene_json(o, scene, motion_source, anchor, ref, poses, stats, delays).dump(2) + "\n");

    staged.commit();
  } catch (const fs::filesystem_error& e) {
    throw Error("synth: writing '" + final_dir.string() + "' failed: " + e.what());
  }
  return final_dir.string();
}

std::string render_sequence(const SynthOptions& o, const std::string& output_dir) {
  validate(o);  // before the motion is generated for the requested span
  HandheldMotionOptions h = o.handheld;
  h.seed = o.seed;
  // Cover the requested frames plus one second of slack.
  const double clock_span = o.start_offset_s + (o.frames - 1) / o.fps + 1.0;
  // Played time_scale times faster, the motion must last time_scale times longer.
  const double span = o.time_scale == 1.0 ? clock_span : clock_span * o.time_scale;
  if (!(span * h.rate_hz < static_cast<double>(io::input_limits().max_list_entries))) {
    std::ostringstream m;
    m << "synth: --start " << o.start_offset_s << " s and --frames " << o.frames << " at --fps " << o.fps << " need "
      << span << " s of generated motion, more than " << io::input_limits().max_list_entries << " poses at "
      << h.rate_hz << " Hz (the list limit; raise with --max-list-entries)";
    throw Error(m.str());
  }
  h.duration_s = std::max(h.duration_s, span);
  return render_sequence(o, generate_handheld_motion(h), output_dir,
                         "generated hand-held motion (seed " + std::to_string(o.seed) + ")");
}

}  // namespace bivo::odometry::synth
