// Streaming a sequence through the tracker: frames loaded in order (io::FrameStream), each
// prepared once (beside the pair before it), pairs estimated coarse to fine, poses chained.
#include "odometry/sequence_tracking.h"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <exception>
#include <optional>
#include <utility>

#include "odometry/io/frame_stream.h"
#include "odometry/io/vignetting.h"
#include "odometry/kernels/kernels.h"
#include "solvers/error.h"

namespace bivo::odometry {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

}  // namespace

StreamStep estimate_motion_preparing_next(const PreparedFrame& reference, const PreparedFrame& current,
                                          const Eigen::Isometry3d& initial, const TrackerOptions& options,
                                          std::optional<io::RgbdImage> next_image, const io::Intrinsics& K) {
  StreamStep step;
  run_beside(
      options.problem.threads, [&] { step.pair = estimate_motion_from_prior(reference, current, initial, options); },
      [&] {
        if (!next_image) return;
        const auto t0 = Clock::now();
        step.next = prepare_frame(std::move(*next_image), K, options.levels, options.problem.threads,
                                  options.finest_level, reads_frame_statistics(parse_method(options.method)));
        step.next_prepare_seconds = seconds_since(t0);
      });
  return step;
}

FrameWindow frame_window(int total, const TrackerOptions& options, const std::string& directory) {
  // In 64 bits: first_frame + 1 and first_frame + max_frames may exceed INT_MAX.
  const std::int64_t first = options.first_frame;
  if (first < 0 || first + 1 >= total) {
    throw Error("sequence '" + directory + "' has " + std::to_string(total) + " associated frames; first frame " +
                std::to_string(first) + " leaves fewer than 2 to process");
  }
  const std::int64_t end = options.max_frames < 0 ? total : std::min<std::int64_t>(total, first + options.max_frames);
  return {static_cast<int>(first), static_cast<int>(end)};
}

io::SequenceOptions sequence_options(const TrackerOptions& options) {
  io::SequenceOptions so;
  so.max_association_dt = options.max_association_dt;
  so.intrinsics = options.intrinsics;
  so.distortion = options.distortion;
  return so;
}

TrackResult track_sequence(const std::string& directory, const TrackerOptions& options,
                           const std::function<void(const PairResult&)>& on_pair) {
  validate(options);
  return track_sequence(io::open_tum_sequence(directory, sequence_options(options)), options, on_pair);
}

TrackerOptions with_stated_sensor(TrackerOptions options, std::optional<double> readout,
                                  std::optional<double> vignetting) {
  if (options.readout_time < 0.0) options.readout_time = readout.value_or(0.0);
  if (options.vignetting < 0.0) options.vignetting = vignetting.value_or(0.0);
  return options;
}

TrackResult track_sequence(const io::TumSequence& seq, const TrackerOptions& given,
                           const std::function<void(const PairResult&)>& on_pair) {
  validate(given);
  const TrackerOptions options = with_stated_sensor(given, seq.readout_time, seq.vignetting);
  const FrameWindow window = frame_window(static_cast<int>(seq.frames.size()), options, seq.directory);
  const int first_index = window.begin, end = window.end;

  TrackResult out;
  out.sequence = seq.name;
  out.intrinsics = seq.intrinsics;
  out.readout_time = options.readout_time;
  out.vignetting = options.vignetting;

  // Loading runs ahead on threads of its own (options.prefetch_frames, load_threads). A pair's
  // CPU time is the process's (this thread's and the per-pixel workers') less the loaders'.
  const int threads = options.problem.threads;
  io::FrameStream frames(seq.frames, first_index, end, seq.intrinsics, seq.distortion, load_threads_for(options),
                         options.vignetting);
  const auto cpu_seconds = [&frames] { return process_cpu_seconds() - frames.loader_cpu_seconds(); };
  io::RgbdImage first = frames.next();
  out.load_seconds += frames.last_wait_seconds();
  auto t_prep = Clock::now();
  const bool statistics = reads_frame_statistics(parse_method(options.method));
  PreparedFrame reference =
      prepare_frame(std::move(first), seq.intrinsics, options.levels, threads, options.finest_level, statistics);
  out.profile.add("pyramid", seconds_since(t_prep));

  Eigen::Isometry3d T_w_ref = Eigen::Isometry3d::Identity();
  if (options.start_at_groundtruth && seq.groundtruth) {
    if (const auto T0 = io::interpolate_pose(*seq.groundtruth, seq.frames[first_index].rgb_time)) T_w_ref = *T0;
  }
  out.trajectory.push_back({seq.frames[first_index].rgb_time, T_w_ref});

  // Each frame is prepared once: the current frame of pair k is the reference of pair k + 1.
  // With one thread a pair's current frame is prepared right before its estimate, which then
  // finds the pyramid in cache (preparing it one pair ahead cost 5-8 % per pair). With more,
  // it is prepared while the pair before is estimated (sequence_tracking.h), and a pair's time
  // is its estimate plus the next pair's preparation. The first pair's time holds its own
  // current frame's preparation either way.
  const bool ahead = threads > 1;
  PreparedFrame current;
  Eigen::Isometry3d velocity = Eigen::Isometry3d::Identity();  // T_21 of the last valid pair
  for (int k = first_index + 1; k < end; ++k) {
    double lead_seconds = 0.0, lead_cpu = 0.0, load_seconds = 0.0;
    if (k == first_index + 1 || !ahead) {  // frame k, this pair's current frame
      io::RgbdImage image = frames.next();
      load_seconds += frames.last_wait_seconds();
      t_prep = Clock::now();
      const double cpu0 = cpu_seconds();
      current =
          prepare_frame(std::move(image), seq.intrinsics, options.levels, threads, options.finest_level, statistics);
      lead_seconds = seconds_since(t_prep);
      lead_cpu = cpu_seconds() - cpu0;
    }
    // Frame k + 1, prepared ahead. An error loading it is thrown after this pair is delivered,
    // as it is without preparing ahead.
    std::optional<io::RgbdImage> next_image;
    std::exception_ptr load_error;
    if (ahead && k + 1 < end) {
      try {
        next_image = frames.next();
      } catch (const Error&) {
        load_error = std::current_exception();
      }
      load_seconds += frames.last_wait_seconds();
    }
    out.load_seconds += load_seconds;

    const Eigen::Isometry3d prior =
        options.initial_guess == InitialGuess::kConstantVelocity ? velocity : Eigen::Isometry3d::Identity();
    const auto t_step = Clock::now();
    const double cpu0 = cpu_seconds();
    StreamStep step =
        estimate_motion_preparing_next(reference, current, prior, options, std::move(next_image), seq.intrinsics);
    PairResult pair = std::move(step.pair);
    pair.index = k - 1;
    pair.profile.add("pyramid", lead_seconds + step.next_prepare_seconds);
    pair.seconds = lead_seconds + seconds_since(t_step);
    pair.cpu_seconds = lead_cpu + (cpu_seconds() - cpu0);
    pair.load_seconds = load_seconds;
    if (pair.valid) {
      velocity = pair.T_21;
      const double t1 = reference.pyramid.timestamp, t2 = current.pyramid.timestamp;
      if (t2 > t1) {
        current.arrival_velocity = solvers::se3::log(pair.T_21) / (t2 - t1);
        current.arrival_time = 0.5 * (t1 + t2);
      }
    } else {
      ++out.invalid_pairs;
    }
    const Eigen::Isometry3d T_w_cur = T_w_ref * pair.T_21.inverse();
    pair.T_wc = T_w_cur;
    if (seq.groundtruth) {
      if (const auto gt =
              io::groundtruth_motion(*seq.groundtruth, seq.frames[k - 1].rgb_time, seq.frames[k].rgb_time)) {
        pair.error = io::pose_error(pair.T_21, *gt);
      }
    }
    out.trajectory.push_back({seq.frames[k].rgb_time, T_w_cur});
    out.profile.merge(pair.profile);
    if (on_pair) on_pair(pair);
    out.pairs.push_back(std::move(pair));
    T_w_ref = T_w_cur;
    reference = std::move(current);
    current = std::move(step.next);
    if (load_error) std::rethrow_exception(load_error);
  }
  return out;
}

FramePair load_frame_pair(const std::string& directory, int reference_index, int current_index,
                          const TrackerOptions& options) {
  const io::TumSequence seq = io::open_tum_sequence(directory, sequence_options(options));
  const int n = static_cast<int>(seq.frames.size());
  for (int i : {reference_index, current_index}) {
    if (i < 0 || i >= n) {
      throw Error("frame index " + std::to_string(i) + " outside 0.." + std::to_string(n - 1) + " of '" + directory +
                  "'");
    }
  }
  FramePair p;
  p.sequence = seq.name;
  p.reference_frame = seq.frames[reference_index];
  p.current_frame = seq.frames[current_index];
  p.readout_time = seq.readout_time;
  p.vignetting = with_stated_sensor(options, seq.readout_time, seq.vignetting).vignetting;
  io::RgbdImage a = io::load_rgbd_image(p.reference_frame);
  io::RgbdImage b = io::load_rgbd_image(p.current_frame, a.width, a.height);
  io::divide_out_vignetting(a, p.vignetting, seq.intrinsics);
  io::divide_out_vignetting(b, p.vignetting, seq.intrinsics);
  const io::Undistortion undistortion(seq.intrinsics, seq.distortion, a.width, a.height);
  undistortion.apply(a);
  undistortion.apply(b);
  p.reference = prepare_frame(a, seq.intrinsics, options.levels, options.problem.threads);
  p.current = prepare_frame(b, seq.intrinsics, options.levels, options.problem.threads);
  if (seq.groundtruth) {
    p.groundtruth_T21 = io::groundtruth_motion(*seq.groundtruth, p.reference_frame.rgb_time, p.current_frame.rgb_time);
  }
  return p;
}

}  // namespace bivo::odometry
