#include "experiments/sequence_runner.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include <nlohmann/json.hpp>

#include "experiments/progress_bar.h"
#include "experiments/result_table.h"
#include "experiments/tracker_config.h"
#include "odometry/io/atomic_file.h"
#include "odometry/io/pose_error.h"
#include "odometry/io/tum_dataset.h"
#include "solvers/error.h"

namespace bivo::experiments {

std::string effective_backend(const odometry::TrackerOptions& options) {
  return options.backend.empty() ? odometry::default_backend(odometry::parse_method(options.method)) : options.backend;
}

odometry::TrackerOptions with_frame_window(odometry::TrackerOptions tracker, int first_frame, int max_frames) {
  tracker.first_frame = first_frame;
  tracker.max_frames = max_frames;
  return tracker;
}

RunOutcome run_sequence(const RunRequest& request, const std::function<void(const odometry::PairResult&)>& on_pair) {
  const odometry::TrackerOptions options = with_frame_window(request.tracker, request.first_frame, request.max_frames);
  odometry::validate(options);
  const auto opened = request.opened ? request.opened : open_run_sequence(request);
  const odometry::io::TumSequence& seq = *opened;
  // The window's size for the progress bar; track_sequence checks it.
  const odometry::FrameWindow window =
      odometry::frame_window(static_cast<int>(seq.frames.size()), options, request.sequence_dir);
  ProgressBar bar(request.label.empty() ? seq.name + " " + options.method : request.label,
                  window.end - window.begin - 1, request.progress);

  odometry::TrackResult track = odometry::track_sequence(seq, options, [&](const odometry::PairResult& pair) {
    if (on_pair) on_pair(pair);
    bar.tick();
  });
  bar.finish();

  RunOutcome out;
  out.sequence = track.sequence;
  out.method = options.method;
  out.backend = effective_backend(options);
  out.groundtruth = seq.groundtruth;
  out.trajectory = std::move(track.trajectory);
  out.pairs = std::move(track.pairs);
  out.profile = track.profile;
  out.failures = track.invalid_pairs;
  out.load_seconds = track.load_seconds;
  out.readout_time = track.readout_time;
  out.vignetting = track.vignetting;

  const auto median_and_mean = [&](double odometry::PairResult::*field, double& median, double& mean) {
    std::vector<double> ms;
    for (const auto& p : out.pairs) ms.push_back(1000.0 * (p.*field));
    if (ms.empty()) throw Error("run on '" + request.sequence_dir + "' processed no frame pair");
    double sum = 0;
    for (double v : ms) sum += v;
    mean = sum / double(ms.size());
    std::sort(ms.begin(), ms.end());
    const size_t n = ms.size();
    median = n % 2 ? ms[n / 2] : 0.5 * (ms[n / 2 - 1] + ms[n / 2]);
  };
  median_and_mean(&odometry::PairResult::seconds, out.median_ms, out.mean_ms);
  median_and_mean(&odometry::PairResult::cpu_seconds, out.median_cpu_ms, out.mean_cpu_ms);
  return out;
}

std::string run_summary_line(const RunOutcome& run) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(3) << "frames=" << run.trajectory.size() << " median_ms=" << run.median_ms
    << " mean_ms=" << run.mean_ms << " median_cpu_ms=" << run.median_cpu_ms << " mean_cpu_ms=" << run.mean_cpu_ms
    << " failures=" << run.failures;
  return s.str();
}

void write_pair_log(std::ostream& o, const RunOutcome& run) {
  o << "pair,t_reference,t_current,valid,iterations,ms,cpu_ms,load_ms,lambda,epsilon,mu,epsilon_per_weight,f_i,"
       "f_d,trans_err_m,rot_err_deg,correlation,relaxed_levels,trust,note\n";
  for (const auto& p : run.pairs) {
    o << std::setprecision(17) << p.index << "," << p.t_reference << "," << p.t_current << "," << (p.valid ? 1 : 0)
      << "," << p.iterations << std::setprecision(8) << "," << 1000.0 * p.seconds << "," << 1000.0 * p.cpu_seconds
      << "," << 1000.0 * p.load_seconds << "," << p.lambda << "," << p.epsilon << "," << p.mu << ","
      << p.epsilon_per_weight << ",";
    if (std::isfinite(p.f_i)) o << p.f_i;
    o << ",";
    if (std::isfinite(p.f_d)) o << p.f_d;
    o << ",";
    if (p.error)
      o << p.error->translation_m << "," << p.error->rotation_deg;
    else
      o << ",";
    o << "," << p.correlation << "," << p.relaxed_levels << "," << p.trust << "," << csv_field(p.note) << "\n";
  }
}

void write_pair_log(const std::string& path, const RunOutcome& run) {
  odometry::io::write_file_atomically(path, [&](std::ostream& o) { write_pair_log(o, run); });
}

std::shared_ptr<const odometry::io::TumSequence> open_run_sequence(const RunRequest& request) {
  return std::make_shared<const odometry::io::TumSequence>(
      odometry::io::open_tum_sequence(request.sequence_dir, odometry::sequence_options(request.tracker)));
}

std::vector<NamedPath> run_input_files(const RunRequest& request) {
  const auto opened = request.opened ? request.opened : open_run_sequence(request);
  const odometry::io::TumSequence& seq = *opened;
  std::vector<NamedPath> inputs;
  for (const auto& f : seq.list_files) inputs.push_back({"sequence list", f});
  // The sequence's other TUM lists too (e.g. rgb.txt beside associations.txt): never outputs.
  for (const char* list : {"rgb.txt", "depth.txt", "associations.txt", "groundtruth.txt", "scene.json"}) {
    inputs.push_back({"sequence list", (std::filesystem::path(request.sequence_dir) / list).string()});
  }
  for (const auto& f : seq.frames) {
    inputs.push_back({"image listed at " + f.origin, f.rgb_path});
    inputs.push_back({"image listed at " + f.origin, f.depth_path});
  }
  return inputs;
}

void write_run_outputs(const RunOutcome& run, const odometry::TrackerOptions& config, const RunOutputPaths& paths) {
  odometry::io::StagedOutputs out;
  if (!paths.trajectory.empty()) {
    out.add(paths.trajectory,
            [&](std::ostream& o) { odometry::io::write_tum_trajectory(o, run.trajectory, paths.trajectory); });
  }
  if (!paths.log.empty()) out.add(paths.log, [&](std::ostream& o) { write_pair_log(o, run); });
  const std::string config_text = tracker_options_to_json(config).dump(2) + "\n";
  for (const std::string& path : paths.configs) {
    if (!path.empty()) out.add(path, [&](std::ostream& o) { o << config_text; });
  }
  out.commit();
}

}  // namespace bivo::experiments
