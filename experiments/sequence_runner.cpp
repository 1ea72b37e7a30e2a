#include "experiments/sequence_runner.h"

#include <algorithm>
#include <iomanip>
#include <sstream>

#include "experiments/progress_bar.h"
#include "experiments/result_table.h"
#include "odometry/io/atomic_file.h"
#include "odometry/io/pose_error.h"
#include "odometry/io/tum_dataset.h"
#include "solvers/error.h"

namespace bivo::experiments {

std::string effective_backend(const odometry::TrackerOptions& options) {
  return options.backend.empty() ? odometry::default_backend(odometry::parse_method(options.method))
                                 : options.backend;
}

RunOutcome run_sequence(const RunRequest& request,
                        const std::function<void(const odometry::PairResult&)>& on_pair) {
  odometry::TrackerOptions options = request.tracker;
  options.first_frame = request.first_frame;
  options.max_frames = request.max_frames;
  odometry::validate(options);
  // Peek at the window's size for the progress bar; track_sequence re-checks it.
  odometry::io::SequenceOptions so;
  so.max_association_dt = options.max_association_dt;
  so.intrinsics = options.intrinsics;
  const odometry::io::TumSequence seq = odometry::io::open_tum_sequence(request.sequence_dir, so);
  const int total = int(seq.frames.size());
  const int end = request.max_frames < 0 ? total : std::min(total, request.first_frame + request.max_frames);
  ProgressBar bar(request.label.empty() ? seq.name + " " + options.method : request.label,
                  std::max(0, end - request.first_frame - 1), request.progress);

  odometry::TrackResult track = odometry::track_sequence(request.sequence_dir, options,
                                                         [&](const odometry::PairResult& pair) {
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

  std::vector<double> ms;
  for (const auto& p : out.pairs) ms.push_back(1000.0 * p.seconds);
  double sum = 0;
  for (double v : ms) sum += v;
  out.mean_ms = sum / double(ms.size());
  std::sort(ms.begin(), ms.end());
  const size_t n = ms.size();
  out.median_ms = n % 2 ? ms[n / 2] : 0.5 * (ms[n / 2 - 1] + ms[n / 2]);
  return out;
}

std::string run_summary_line(const RunOutcome& run) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(3) << "frames=" << run.trajectory.size() << " median_ms=" << run.median_ms
    << " mean_ms=" << run.mean_ms << " failures=" << run.failures;
  return s.str();
}

void write_pair_log(const std::string& path, const RunOutcome& run) {
  odometry::io::write_file_atomically(path, [&](std::ostream& o) {
    o << "pair,t_reference,t_current,valid,iterations,ms,load_ms,lambda,epsilon,mu,epsilon_per_weight,f_i,f_d,"
         "trans_err_m,rot_err_deg,correlation,relaxed_levels,note\n";
    for (const auto& p : run.pairs) {
      o << std::setprecision(17) << p.index << "," << p.t_reference << "," << p.t_current << ","
        << (p.valid ? 1 : 0) << "," << p.iterations << std::setprecision(8) << "," << 1000.0 * p.seconds << ","
        << 1000.0 * p.load_seconds << "," << p.lambda << "," << p.epsilon << "," << p.mu << ","
        << p.epsilon_per_weight << "," << p.f_i << "," << p.f_d << ",";
      if (p.error) o << p.error->translation_m << "," << p.error->rotation_deg;
      else o << ",";
      o << "," << p.correlation << "," << p.relaxed_levels << "," << csv_field(p.note) << "\n";
    }
  });
}

}  // namespace bivo::experiments
