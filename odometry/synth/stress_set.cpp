#include "odometry/synth/stress_set.h"

#include <filesystem>

#include <nlohmann/json.hpp>

#include "odometry/io/atomic_file.h"
#include "odometry/io/staged_folder.h"
#include "odometry/io/trajectory.h"
#include "odometry/synth/benchmark_set.h"
#include "solvers/error.h"

namespace bivo::odometry::synth {

namespace fs = std::filesystem;

SensorDefects stress_depth_and_image_defects() {
  SensorDefects d;
  d.bias_radial = 0.02;    // 2 % at the corner at 1 m (Smisek et al. 2011: radial, up to a few %)
  d.bias_lowfreq = 0.008;  // low-frequency pattern (Herrera et al. 2012: per-pixel disparity distortion)
  d.bias_wavelength_px = 300.0;
  d.depth_offset_m = Eigen::Vector3d(0.004, 0.002, 0.0);    // 2.1 / 1.1 px at 1 m
  d.depth_rotation_rad = Eigen::Vector3d(0.0, 0.002, 0.0);  // 1.1 px at any depth
  d.static_noise_share = 0.8;  // fr3's pair residual: 0.86e-3 z^2 against 2.3e-3 for independent noise
  // No colour-depth delay: the freiburg3 sensor family records both together (TUM fr3 lists: 0 ms).
  d.gain_step = 0.03;
  d.gain_memory = 0.9;
  // Vignetting per profile (below): `bivo depth-stats` measures each real sensor's fall-off.
  return d;
}

void apply_stress_profile(const std::string& profile, SynthOptions& o) {
  if (profile != "deep" && profile != "fast") throw Error("stress profile must be deep or fast, got '" + profile + "'");
  o.render.defects = stress_depth_and_image_defects();
  if (profile == "deep") {
    // Far background: the wall 3.5 m behind the zig-zag, seen over it (pitch 12 deg instead
    // of 27); the plane seen from 2.6 m.
    o.layout.wall_behind_m = 3.5;
    if (o.category.structure)
      o.layout.pitch_deg = 12.0;
    else
      o.layout.distance_m = 2.6;
    o.render.depth.max_range_m = 8.0;
    // The freiburg3 sensor's far depth: the real fr3 residual's spread grows as z^3.0 at the
    // true motion (a z^2 model gives 0.8), 0.86e-3 z^2 at its median 2.4 m; with the 80 %
    // fixed pattern that is sigma_z = 5.6e-4 z^3 (8.7 mm at 2.5 m, as z^2 gave; 3.6 cm at 4 m).
    SensorDefects& d = o.render.defects;
    o.render.depth.noise_coeff = 5.6e-4;
    d.noise_exponent = 3.0;
    // Its pairs' mean offsets (0.07 % RMS): 0.009 px of disparity frame to frame.
    d.disparity_offset_step_px = 0.009;
    // Its outliers (0.7 % of compared pixels): flying pixels and speckle failures.
    d.speckle_outliers = 0.003;
    d.flying_pixels = 0.5;
    // No colour fall-off: real fr3/long_office_household measures 0.00.
    d.vignetting = 0.0;
    return;
  }
  // Shaking hand-held motion, 0.9 m/s and 120 deg/s (3 cm and 4 deg per frame at 30 Hz on
  // average, peaks of 6-8 deg and 5 cm), at 0.8-2.5 Hz so the scene stays in view.
  o.handheld.mean_linear_speed_mps = 0.9;
  o.handheld.mean_angular_speed_dps = 120.0;
  o.handheld.min_frequency_hz = 0.8;
  o.handheld.max_frequency_hz = 2.5;
  // The freiburg1 sensor: noisier depth, recorded unsynchronized (0-14 ms), a milder
  // distortion; the fixed pattern does not cancel at this speed anyway.
  SensorDefects& d = o.render.defects;
  o.render.depth.noise_coeff = 2.4e-3;
  // Its depth error correlated over a wider window: the real fr1/rpy residual's correlation
  // length is 5.6 px over all its pairs; 2 px (the renderer's default) gives 3.5-3.8 px in
  // scenes as deep as the recording's, 3 px gives 5.4.
  o.render.depth.noise_correlation_px = 3.0;
  d.static_noise_share = 0.0;
  d.bias_radial = 0.01;
  d.bias_lowfreq = 0.004;
  d.depth_delay_min_s = 0.0;
  d.depth_delay_max_s = 0.014;
  d.readout_s = 0.025;  // rolling shutter over most of the 33 ms frame
  d.exposure_s = 0.010;
  d.blur_samples = 4;
  // Real fr1/rpy pairs' mean offsets (0.23 % RMS at ~1.1 m): 0.05 px of disparity frame to
  // frame; its 1.5 % outliers: speckle failures and flying pixels.
  d.disparity_offset_step_px = 0.05;
  d.speckle_outliers = 0.008;
  d.flying_pixels = 0.5;
  // Real fr1/rpy's colour fall-off: 1 - 0.10 rho^2.
  d.vignetting = 0.10;
}

std::vector<StressSequence> stress_set(int frames) {
  std::vector<StressSequence> out;
  for (const char* profile : {"deep", "fast"}) {
    const bool deep = std::string(profile) == "deep";
    for (const SynthCategory& c0 : all_categories()) {
      if (c0.near != !deep) continue;  // deep: the far views; fast: the near ones
      StressSequence s;
      SynthOptions& o = s.options;
      o.category = c0;
      o.frames = frames;
      o.seed = kBenchmarkSeed;
      apply_stress_profile(profile, o);
      if (deep) s.trajectory = benchmark_sequence(c0.name()).trajectory;
      s.name = std::string("rgbd_dataset_freiburg3_stress_") + profile + "_" + c0.name();
      o.sequence_name = s.name;
      out.push_back(s);
    }
  }
  // Textured deep views along three more real motions, each with its own bias field (seed):
  // biased depth misleads most where the image has texture, and a protocol that holds one
  // such sequence out must still have others to learn from.
  struct Extra {
    const char* category;
    const char* trajectory;
    double start_s;
    std::uint64_t seed;
    const char* motion;
  };
  for (const Extra& e :
       {Extra{"structure_texture_far", "rgbd_dataset_freiburg2_desk-groundtruth.txt", 50.0, 2, "desk"},
        Extra{"structure_texture_far", "rgbd_dataset_freiburg1_desk-groundtruth.txt", 5.0, 3, "fastdesk"},
        Extra{"nostructure_texture_far", "rgbd_dataset_freiburg2_xyz-groundtruth.txt", 20.0, 4, "xyz"}}) {
    StressSequence s;
    SynthOptions& o = s.options;
    o.category = parse_category(e.category);
    o.frames = frames;
    o.seed = e.seed;
    o.start_offset_s = e.start_s;
    apply_stress_profile("deep", o);
    s.trajectory = e.trajectory;
    s.name = std::string("rgbd_dataset_freiburg3_stress_deep_") + e.category + "_" + e.motion;
    o.sequence_name = s.name;
    out.push_back(s);
  }
  return out;
}

std::vector<std::string> render_stress_set(const std::string& trajectories_dir, const std::string& output_dir,
                                           int frames, const std::string& only, int threads, bool replace_own_folder) {
  std::vector<StressSequence> entries;
  for (const StressSequence& s : stress_set(frames)) {
    if (only.empty() || s.name.find(only) != std::string::npos) entries.push_back(s);
  }
  if (entries.empty()) throw Error("stress set: no sequence name contains '" + only + "'");
  for (const StressSequence& s : entries) {
    if (!s.trajectory.empty() && !fs::is_regular_file(fs::path(trajectories_dir) / s.trajectory)) {
      throw Error("stress set: trajectory '" + (fs::path(trajectories_dir) / s.trajectory).string() + "' (for " +
                  s.name + ") not found; pass the folder holding the TUM *-groundtruth.txt files");
    }
  }
  for (StressSequence& s : entries) {
    s.options.replace_own_folder = replace_own_folder;
    io::check_folder_target((fs::path(output_dir) / s.options.sequence_name).string(), replace_own_folder);
  }
  std::vector<std::string> dirs;
  nlohmann::json sequences = nlohmann::json::array();
  for (StressSequence& s : entries) {
    s.options.threads = threads;
    if (s.trajectory.empty()) {
      dirs.push_back(render_sequence(s.options, output_dir));
    } else {
      const std::string path = (fs::path(trajectories_dir) / s.trajectory).string();
      dirs.push_back(render_sequence(s.options, io::read_tum_trajectory(path), output_dir, s.trajectory));
    }
    sequences.push_back({{"name", s.name},
                         {"category", s.options.category.name()},
                         {"motion", s.trajectory.empty() ? "generated" : s.trajectory},
                         {"digest_fnv1a64", sequence_digest(dirs.back())}});
  }
  const nlohmann::json manifest{{"generator", "bivo synth --stress-set"}, {"frames", frames}, {"sequences", sequences}};
  const std::string file = only.empty() ? "stress_set.json" : "stress_set." + only + ".json";
  io::write_file_atomically((fs::path(output_dir) / file).string(),
                            [&](std::ostream& out) { out << manifest.dump(2) << "\n"; });
  return dirs;
}

}  // namespace bivo::odometry::synth
