// `bivo synth`: renders one synthetic "Structure vs. Texture" RGB-D sequence in TUM format
// along a real ground-truth trajectory (--trajectory) or generated hand-held motion, or the
// fixed benchmark set of all eight categories (--benchmark-set, odometry/synth/benchmark_set.h),
// or the stress set with real sensor defects (--stress-set, odometry/synth/stress_set.h).
#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "experiments/cli/commands.h"
#include "experiments/output_set.h"
#include "odometry/io/atomic_file.h"
#include "odometry/io/staged_folder.h"
#include "odometry/io/trajectory.h"
#include "odometry/synth/benchmark_set.h"
#include "odometry/synth/sequence.h"
#include "odometry/synth/stress_set.h"
#include "solvers/error.h"

namespace bivo::experiments::cli {

namespace {

namespace fs = std::filesystem;

struct SynthArgs {
  std::string category, distance, trajectory, output, trajectories, stress_profile;
  odometry::synth::SynthOptions options;
  bool no_noise = false, benchmark_set = false, stress_set = false, force = false;
  std::vector<double> depth_offset, depth_rotation, depth_delay;
  std::vector<std::string> without;  // defect classes a stress profile is rendered without
};

// Options that would change a benchmark rendering: refused with --benchmark-set.
const char* const kPerSequenceOptions[] = {"--distance",
                                           "--trajectory",
                                           "--frames",
                                           "--seed",
                                           "--name",
                                           "--start",
                                           "--fps",
                                           "--supersampling",
                                           "--depth-noise",
                                           "--disparity-step",
                                           "--max-range",
                                           "--read-noise",
                                           "--shot-noise",
                                           "--exposure-jitter",
                                           "--speed",
                                           "--angular-speed",
                                           "--no-noise",
                                           "--depth-bias-radial",
                                           "--depth-bias-lowfreq",
                                           "--depth-bias-wavelength",
                                           "--depth-offset",
                                           "--depth-rotation",
                                           "--depth-delay",
                                           "--readout",
                                           "--exposure",
                                           "--blur-samples",
                                           "--gain-step",
                                           "--vignetting",
                                           "--time-scale",
                                           "--wall-behind",
                                           "--view-distance",
                                           "--view-pitch",
                                           "--static-depth-noise",
                                           "--depth-noise-exponent",
                                           "--depth-noise-correlation",
                                           "--disparity-offset",
                                           "--disparity-offset-memory",
                                           "--speckle-outliers",
                                           "--flying-pixels",
                                           "--without"};

// What a stress profile fixes: every rendering flag but the motion, length and naming ones.
bool motion_or_naming(const std::string& name) {
  for (const char* keep : {"--distance", "--trajectory", "--frames", "--seed", "--name", "--start", "--fps",
                           "--time-scale", "--speed", "--angular-speed"}) {
    if (name == keep) return true;
  }
  return false;
}

// The scene's layout flags and what they set: a profile's sensor may be placed in a scene
// whose depths match a real recording's (docs/results/stress-set.md).
struct LayoutFlag {
  const char* name;
  double odometry::synth::SceneLayout::*field;
};
constexpr LayoutFlag kLayoutFlags[] = {{"--wall-behind", &odometry::synth::SceneLayout::wall_behind_m},
                                       {"--view-distance", &odometry::synth::SceneLayout::distance_m},
                                       {"--view-pitch", &odometry::synth::SceneLayout::pitch_deg}};

bool scene_layout(const std::string& name) {
  for (const LayoutFlag& f : kLayoutFlags) {
    if (name == f.name) return true;
  }
  return false;
}

void refuse_per_sequence_options(const CLI::App& cmd, const char* set, bool allow_frames) {
  for (const char* name : kPerSequenceOptions) {
    if (allow_frames && std::string(name) == "--frames") continue;
    if (cmd.get_option(name)->count() > 0) {
      throw Error(std::string("synth: ") + set + " fixes every rendering parameter; drop " + name);
    }
  }
}

void run_stress_set(const SynthArgs& a, const CLI::App& cmd) {
  refuse_per_sequence_options(cmd, "--stress-set", true);
  if (a.trajectories.empty()) {
    throw Error(
        "synth: --stress-set needs --trajectories DIR (the TUM *-groundtruth.txt files, e.g. "
        "../shared/data/trajectories)");
  }
  const int frames = cmd.get_option("--frames")->count() > 0 ? a.options.frames : odometry::synth::kStressFrames;
  for (const std::string& dir :
       odometry::synth::render_stress_set(a.trajectories, a.output, frames, a.category, a.options.threads, a.force)) {
    std::cout << dir << "\n";
  }
}

// "x y z" flags: exactly three numbers or none.
Eigen::Vector3d vector3(const std::vector<double>& v, const char* flag) {
  if (v.empty()) return Eigen::Vector3d::Zero();
  if (v.size() != 3) throw Error(std::string("synth: ") + flag + " takes 3 numbers, got " + std::to_string(v.size()));
  return Eigen::Vector3d(v[0], v[1], v[2]);
}

void run_benchmark_set(const SynthArgs& a, const CLI::App& cmd) {
  refuse_per_sequence_options(cmd, "--benchmark-set", false);
  if (a.trajectories.empty()) {
    throw Error(
        "synth: --benchmark-set needs --trajectories DIR (the TUM *-groundtruth.txt files, e.g. "
        "../shared/data/trajectories)");
  }
  const auto t0 = std::chrono::steady_clock::now();
  for (const std::string& dir :
       odometry::synth::render_benchmark_set(a.trajectories, a.output, a.category, a.options.threads, a.force)) {
    std::cout << dir << "\n";
  }
  std::cerr << "synth: benchmark set rendered in " << std::fixed << std::setprecision(1)
            << std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() << " s\n";
}

// `path` lies in `folder` (after resolving symlinks and "..", or as a hard link to a file there).
bool is_inside(const std::string& path, const fs::path& folder) {
  std::error_code ec;
  const fs::path file = fs::weakly_canonical(fs::absolute(path), ec);
  const fs::path dir = fs::weakly_canonical(fs::absolute(folder), ec);
  for (fs::path p = file; !p.empty() && p != p.root_path(); p = p.parent_path()) {
    if (p == dir) return true;
  }
  if (!fs::is_directory(folder, ec)) return false;
  for (fs::recursive_directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code e;
    if (it->is_regular_file(e) && fs::equivalent(it->path(), path, e)) return true;
  }
  return false;
}

void run_synth(const SynthArgs& a, const CLI::App& cmd) {
  namespace synth = odometry::synth;
  check_output_folder({"--output", a.output});
  if (a.benchmark_set && a.stress_set) throw Error("synth: choose --benchmark-set or --stress-set, not both");
  if (a.benchmark_set) {
    run_benchmark_set(a, cmd);
    return;
  }
  if (a.stress_set) {
    run_stress_set(a, cmd);
    return;
  }
  if (a.category.empty()) throw Error("synth: --category is required (or --benchmark-set)");
  synth::SynthOptions o = a.options;
  o.category = synth::parse_category(a.category, a.distance);
  if (!a.stress_profile.empty()) {
    for (const char* name : kPerSequenceOptions) {
      if (!motion_or_naming(name) && !scene_layout(name) && std::string(name) != "--without" &&
          cmd.get_option(name)->count() > 0) {
        throw Error(std::string("synth: --stress-profile fixes the sensor; drop ") + name);
      }
    }
    const synth::SynthOptions given = o;
    synth::apply_stress_profile(a.stress_profile, o);
    // A layout given on the command line wins over the profile's scene.
    for (const LayoutFlag& f : kLayoutFlags) {
      if (cmd.get_option(f.name)->count() > 0) o.layout.*f.field = given.layout.*f.field;
    }
    for (const std::string& name : a.without) synth::switch_off(o.render.defects, name);
    // Motion given on the command line wins over the profile's generated motion.
    if (cmd.get_option("--speed")->count() > 0) o.handheld.mean_linear_speed_mps = given.handheld.mean_linear_speed_mps;
    if (cmd.get_option("--angular-speed")->count() > 0)
      o.handheld.mean_angular_speed_dps = given.handheld.mean_angular_speed_dps;
  } else if (!a.without.empty()) {
    throw Error("synth: --without needs --stress-profile (without a profile, each defect's own flag sets it)");
  }
  o.render.sensor_noise = !a.no_noise;
  if (!a.depth_offset.empty()) o.render.defects.depth_offset_m = vector3(a.depth_offset, "--depth-offset");
  if (!a.depth_rotation.empty()) o.render.defects.depth_rotation_rad = vector3(a.depth_rotation, "--depth-rotation");
  if (!a.depth_delay.empty()) {
    if (a.depth_delay.size() != 2) throw Error("synth: --depth-delay takes 2 numbers (min max seconds)");
    o.render.defects.depth_delay_min_s = a.depth_delay[0];
    o.render.defects.depth_delay_max_s = a.depth_delay[1];
  }
  o.replace_own_folder = a.force;
  // Before any work: the target may be written, and it does not hold the motion being read.
  const fs::path target =
      fs::path(a.output) / (o.sequence_name.empty() ? synth::default_sequence_name(o.category) : o.sequence_name);
  odometry::io::check_folder_target(target.string(), a.force);
  if (!a.trajectory.empty() && is_inside(a.trajectory, target)) {
    throw Error("synth: --trajectory '" + a.trajectory + "' is inside the output folder '" + target.string() +
                "' (or a hard link to a file there), which rendering replaces; copy it elsewhere first");
  }
  std::string path;
  if (a.trajectory.empty()) {
    path = synth::render_sequence(o, a.output);
  } else {
    path = synth::render_sequence(o, odometry::io::read_tum_trajectory(a.trajectory), a.output, a.trajectory);
  }
  std::cout << path << "\n";
}

}  // namespace

void add_synth_command(CLI::App& app) {
  auto args = std::make_shared<SynthArgs>();
  auto& o = args->options;
  auto* cmd = app.add_subcommand(
      "synth", "Render a synthetic TUM-format RGB-D sequence (Structure vs. Texture) with exact ground truth");
  cmd->add_option("--category", args->category,
                  "structure_texture_near, ..., nostructure_notexture_far (or without _near/_far plus --distance); "
                  "with --benchmark-set: render only this entry");
  cmd->add_option("--distance", args->distance, "near (1.4 m) or far (2.25 m), if not part of --category");
  cmd->add_flag("--benchmark-set", args->benchmark_set,
                "render the fixed benchmark set: all 8 categories, 300 frames each along real fr3 motion, fixed "
                "seeds (byte-identical everywhere); needs --trajectories");
  cmd->add_flag("--stress-set", args->stress_set,
                "render the stress set: 11 sequences with real sensor defects (biased, misregistered, "
                "unsynchronized depth, rolling shutter, blur, gain, vignetting, far background, fast motion); "
                "needs --trajectories; --frames shortens it, --category renders the names containing it");
  cmd->add_option(
         "--trajectories", args->trajectories,
         "--benchmark-set / --stress-set: folder with the TUM *-groundtruth.txt files (../shared/data/trajectories)")
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--trajectory", args->trajectory,
                  "TUM ground-truth trajectory to follow (re-anchored rigidly); default: generated hand-held motion")
      ->check(CLI::ExistingFile);
  cmd->add_option("--frames", o.frames, "number of frames")->capture_default_str();
  cmd->add_option("--seed", o.seed, "seed of textures, sensor noise and generated motion")->capture_default_str();
  cmd->add_option("--output", args->output, "parent folder; the sequence is written to OUTPUT/<sequence name>")
      ->required();
  cmd->add_option("--name", o.sequence_name, "sequence folder name (must contain 'freiburg3')");
  cmd->add_flag("--force", args->force,
                "replace an existing sequence folder that bivo rendered (never one it did not write, nor a symlink)");
  cmd->add_option("--start", o.start_offset_s, "seconds after the trajectory's first pose to start")
      ->capture_default_str();
  cmd->add_option("--fps", o.fps, "frame rate [Hz]")->capture_default_str();
  cmd->add_option("--supersampling", o.render.supersampling, "n x n colour samples per pixel")->capture_default_str();
  cmd->add_option("--depth-noise", o.render.depth.noise_coeff, "depth noise sigma = c z^2: c [1/m]")
      ->capture_default_str();
  cmd->add_option("--disparity-step", o.render.depth.disparity_step_px, "disparity quantization step [px], 0 = off")
      ->capture_default_str();
  cmd->add_option("--max-range", o.render.depth.max_range_m, "largest measured depth [m]")->capture_default_str();
  cmd->add_option("--read-noise", o.render.intensity.read_noise, "intensity read noise sigma [gray levels]")
      ->capture_default_str();
  cmd->add_option("--shot-noise", o.render.intensity.shot_noise_gain, "intensity shot-noise variance per gray level")
      ->capture_default_str();
  cmd->add_option("--exposure-jitter", o.render.intensity.exposure_jitter,
                  "sigma of the per-frame log exposure gain (0 = constant exposure)")
      ->capture_default_str();
  cmd->add_option("--speed", o.handheld.mean_linear_speed_mps, "generated motion: mean linear speed [m/s]")
      ->capture_default_str();
  cmd->add_option("--angular-speed", o.handheld.mean_angular_speed_dps, "generated motion: mean angular speed [deg/s]")
      ->capture_default_str();
  cmd->add_option("--threads", o.threads, "render threads (0 = one per hardware thread)")->capture_default_str();
  cmd->add_flag("--no-noise", args->no_noise, "no random sensor noise and no disparity quantization");
  auto& d = o.render.defects;
  cmd->add_option("--depth-bias-radial", d.bias_radial, "depth bias at the image corner, relative at 1 m (0 = off)");
  cmd->add_option("--depth-bias-lowfreq", d.bias_lowfreq, "RMS of a smooth random depth bias, relative at 1 m");
  cmd->add_option("--depth-bias-wavelength", d.bias_wavelength_px, "shortest wavelength of the smooth bias [px]")
      ->capture_default_str();
  cmd->add_option("--depth-offset", args->depth_offset, "depth camera offset from the colour camera: x y z [m]")
      ->expected(3);
  cmd->add_option("--depth-rotation", args->depth_rotation, "depth camera rotation vector: x y z [rad]")->expected(3);
  cmd->add_option("--depth-delay", args->depth_delay, "depth taken U(min, max) s after colour: min max")->expected(2);
  cmd->add_option("--readout", d.readout_s, "rolling-shutter readout time [s] (0 = global shutter)");
  cmd->add_option("--exposure", d.exposure_s, "exposure time for motion blur [s] (0 = none)");
  cmd->add_option("--blur-samples", d.blur_samples, "poses sampled within the exposure")->capture_default_str();
  cmd->add_option("--gain-step", d.gain_step, "auto-exposure: sigma of the log gain's step per frame (0 = off)");
  cmd->add_option("--vignetting", d.vignetting, "radiance fall-off at the image corner (0 = off)");
  cmd->add_option("--time-scale", o.time_scale, "play the motion this many times faster")->capture_default_str();
  cmd->add_option("--wall-behind", o.layout.wall_behind_m, "structure: wall distance behind the zig-zag [m]")
      ->capture_default_str();
  cmd->add_option("--view-distance", o.layout.distance_m, "nominal camera distance [m] (0 = the category's)");
  cmd->add_option("--view-pitch", o.layout.pitch_deg, "nominal view's downward pitch [deg] (0 = the category's)");
  cmd->add_option("--static-depth-noise", d.static_noise_share,
                  "share of the depth noise variance that is a fixed pattern (0 = off)");
  cmd->add_option("--depth-noise-exponent", d.noise_exponent, "depth noise sigma = c z^p: p")->capture_default_str();
  cmd->add_option("--depth-noise-correlation", o.render.depth.noise_correlation_px,
                  "depth noise correlation: Gaussian sigma [px] (0 = independent pixels)")
      ->capture_default_str();
  cmd->add_option("--disparity-offset", d.disparity_offset_step_px,
                  "per-frame disparity offset at every pixel: sigma of its step [px] (0 = off)");
  cmd->add_option("--disparity-offset-memory", d.disparity_offset_memory, "AR(1) memory of the disparity offset")
      ->capture_default_str();
  cmd->add_option("--speckle-outliers", d.speckle_outliers, "share of pixels with a 2-8 px disparity error (0 = off)");
  cmd->add_option("--flying-pixels", d.flying_pixels,
                  "share of occlusion-band pixels kept at a depth between the edge's sides (0 = off)");
  cmd->add_option("--stress-profile", args->stress_profile,
                  "deep or fast: the stress set's sensor, defects and scene (the layout flags move the scene)");
  cmd->add_option("--without", args->without,
                  "with --stress-profile: render without these defects, comma-separated (" +
                      odometry::synth::defect_class_list() + ")")
      ->delimiter(',');
  cmd->callback([args, cmd] {
    odometry::io::OutputJournal journal;  // a failed rendering takes the folders it made back
    run_synth(*args, *cmd);
    journal.keep();
  });
}

}  // namespace bivo::experiments::cli
