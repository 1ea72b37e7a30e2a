#include "experiments/sequence_runner.h"

#include <algorithm>
#include <chrono>
#include <iomanip>
#include <sstream>

#include "experiments/progress_bar.h"
#include "experiments/result_table.h"
#include "odometry/atomic_file.h"
#include "odometry/pose_error.h"
#include "odometry/tum_dataset.h"
#include "solvers/error.h"

namespace bivo::experiments {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

}  // namespace

std::string effective_backend(const odometry::TrackerOptions& options) {
  return options.backend.empty() ? odometry::default_backend(odometry::parse_method(options.method))
                                 : options.backend;
}

RunOutcome run_sequence(const RunRequest& request,
                        const std::function<void(const odometry::PairResult&)>& on_pair) {
  odometry::TrackerOptions options = request.tracker;
  options.max_frames = -1;
  odometry::validate(options);
  if (request.first_frame < 0) {
    throw Error("--first-frame must be >= 0, got " + std::to_string(request.first_frame));
  }
  if (request.max_frames == 0 || request.max_frames == 1 || request.max_frames < -1) {
    throw Error("--max-frames must be at least 2 (one frame pair), got " + std::to_string(request.max_frames));
  }
  odometry::SequenceOptions so;
  so.max_association_dt = options.max_association_dt;
  so.intrinsics = options.intrinsics;
  const odometry::TumSequence seq = odometry::open_tum_sequence(request.sequence_dir, so);
  const int total = int(seq.frames.size());
  if (request.first_frame + 1 >= total) {
    throw Error("sequence '" + request.sequence_dir + "' has " + std::to_string(total) +
                " associated frames; --first-frame " + std::to_string(request.first_frame) +
                " leaves fewer than 2 to process");
  }
  const int end = request.max_frames < 0 ? total : std::min(total, request.first_frame + request.max_frames);

  RunOutcome out;
  out.sequence = seq.name;
  out.method = options.method;
  out.backend = effective_backend(options);
  out.groundtruth = seq.groundtruth;

  ProgressBar bar(request.label.empty() ? seq.name + " " + options.method : request.label,
                  end - request.first_frame - 1, request.progress);

  auto t_load = Clock::now();
  const odometry::RgbdImage first = odometry::load_rgbd_image(seq.frames[request.first_frame]);
  out.load_seconds += seconds_since(t_load);
  const int width = first.width, height = first.height;
  auto t_prep = Clock::now();
  odometry::PreparedFrame reference = odometry::prepare_frame(first, seq.intrinsics, options.levels);
  // The first frame's pyramid is part of the run but of no pair.
  out.profile.add("pyramid", seconds_since(t_prep));

  const double t_first = seq.frames[request.first_frame].rgb_time;
  Eigen::Isometry3d T_w_ref = Eigen::Isometry3d::Identity();
  if (options.start_at_groundtruth && seq.groundtruth) {
    if (const auto T0 = odometry::interpolate_pose(*seq.groundtruth, t_first)) T_w_ref = *T0;
  }
  out.trajectory.push_back({t_first, T_w_ref});

  Eigen::Isometry3d velocity = Eigen::Isometry3d::Identity();  // T_21 of the last valid pair
  for (int k = request.first_frame + 1; k < end; ++k) {
    t_load = Clock::now();
    const odometry::RgbdImage image = odometry::load_rgbd_image(seq.frames[k], width, height);
    const double load_seconds = seconds_since(t_load);
    out.load_seconds += load_seconds;

    t_prep = Clock::now();
    odometry::PreparedFrame current = odometry::prepare_frame(image, seq.intrinsics, options.levels);
    const double prep_seconds = seconds_since(t_prep);
    const Eigen::Isometry3d prior = options.initial_guess == odometry::InitialGuess::kConstantVelocity
                                        ? velocity
                                        : Eigen::Isometry3d::Identity();
    odometry::PairResult pair = odometry::estimate_motion(reference, current, prior, options);
    pair.index = k - 1;
    pair.t_reference = seq.frames[k - 1].rgb_time;
    pair.t_current = seq.frames[k].rgb_time;
    pair.profile.add("pyramid", prep_seconds);
    pair.seconds += prep_seconds;
    pair.load_seconds = load_seconds;
    if (pair.valid) {
      velocity = pair.T_21;
    } else {
      ++out.failures;
    }
    const Eigen::Isometry3d T_w_cur = T_w_ref * pair.T_21.inverse();
    pair.T_wc = T_w_cur;
    if (seq.groundtruth) {
      if (const auto gt = odometry::groundtruth_motion(*seq.groundtruth, pair.t_reference, pair.t_current)) {
        pair.error = odometry::pose_error(pair.T_21, *gt);
      }
    }
    out.trajectory.push_back({pair.t_current, T_w_cur});
    out.profile.merge(pair.profile);
    if (on_pair) on_pair(pair);
    out.pairs.push_back(std::move(pair));
    T_w_ref = T_w_cur;
    reference = std::move(current);
    bar.tick();
  }
  bar.finish();

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
  odometry::write_file_atomically(path, [&](std::ostream& o) {
    o << "pair,t_reference,t_current,valid,iterations,ms,load_ms,lambda,epsilon,mu,epsilon_per_weight,f_i,f_d,"
         "trans_err_m,rot_err_deg,note\n";
    for (const auto& p : run.pairs) {
      o << std::setprecision(17) << p.index << "," << p.t_reference << "," << p.t_current << ","
        << (p.valid ? 1 : 0) << "," << p.iterations << std::setprecision(8) << "," << 1000.0 * p.seconds << ","
        << 1000.0 * p.load_seconds << "," << p.lambda << "," << p.epsilon << "," << p.mu << ","
        << p.epsilon_per_weight << "," << p.f_i << "," << p.f_d << ",";
      if (p.error) o << p.error->translation_m << "," << p.error->rotation_deg;
      else o << ",";
      o << "," << csv_field(p.note) << "\n";
    }
  });
}

}  // namespace bivo::experiments
