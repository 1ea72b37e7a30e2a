#pragma once
// Runs one odometry method over (a window of) one TUM sequence and keeps what every
// experiment needs: the trajectory, per-pair records, phase times and run statistics.
//
//   RunRequest req;  req.sequence_dir = dir;  req.tracker.method = "bounded";
//   req.first_frame = 10;  req.max_frames = 50;
//   RunOutcome run = run_sequence(req);
//   write_pair_log("pairs.csv", run);  std::cout << run_summary_line(run);
//
// The loop itself is odometry::track_sequence's; this adds the progress bar and the run
// statistics (median/mean time per pair).
#include <functional>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "experiments/output_set.h"
#include "odometry/io/trajectory.h"
#include "odometry/tracker.h"
#include "solvers/profiling.h"

namespace bivo::experiments {

struct RunRequest {
  std::string sequence_dir;
  odometry::TrackerOptions tracker;  // tracker.max_frames is ignored: use first_frame/max_frames
  int first_frame = 0;               // index into the associated frames
  int max_frames = -1;               // frames processed from first_frame (-1: to the end)
  int progress = -1;                 // progress bar: -1 when stderr is a terminal, 0 never, 1 always
  std::string label;                 // progress-bar label; empty: "<sequence> <method>"
  // The sequence as open_run_sequence() opened it, so that one run reads its lists once;
  // null: run_sequence() and run_input_files() open it themselves.
  std::shared_ptr<const odometry::io::TumSequence> opened;
};

// The request's sequence, opened as the tracker opens it (odometry::sequence_options).
std::shared_ptr<const odometry::io::TumSequence> open_run_sequence(const RunRequest& request);

struct RunOutcome {
  std::string sequence;  // folder name
  std::string method, backend;
  odometry::io::Trajectory trajectory;  // one pose per processed rgb frame
  std::optional<odometry::io::Trajectory> groundtruth;
  std::vector<odometry::PairResult> pairs;
  solvers::PhaseProfile profile;              // summed over pairs (loading excluded)
  int failures = 0;                           // pairs whose every level was skipped
  double median_ms = 0, mean_ms = 0;          // wall time per pair, loading excluded
  double median_cpu_ms = 0, mean_cpu_ms = 0;  // CPU time per pair (all threads), loading excluded
  double load_seconds = 0;                    // PNG decoding, all frames
  double readout_time = 0;                    // rolling-shutter readout used [s] (given or stated)
  double vignetting = 0;                      // colour fall-off divided out (given or stated)
};

// `tracker` with a frame window given apart from it (RunRequest, a study's first_frame and
// max_frames), as a run validates it: a study checks its window so before any unit runs.
odometry::TrackerOptions with_frame_window(odometry::TrackerOptions tracker, int first_frame, int max_frames);

// Throws bivo::Error on bad options (odometry::validate), a window outside the sequence
// (naming the frame count) or fewer than 2 frames to process.
RunOutcome run_sequence(const RunRequest& request,
                        const std::function<void(const odometry::PairResult&)>& on_pair = {});

// "frames=N median_ms=X mean_ms=Y median_cpu_ms=A mean_cpu_ms=B failures=K" (no newline).
std::string run_summary_line(const RunOutcome& run);

// Per-pair CSV: pair,t_reference,t_current,valid,iterations,ms,cpu_ms,load_ms,lambda,epsilon,
// mu,epsilon_per_weight,f_i,f_d,trans_err_m,rot_err_deg,correlation,relaxed_levels,trust,note
// (errors empty without ground truth; f_i / f_d empty when not evaluated, see
// TrackerOptions::evaluate_unused_objective).
void write_pair_log(const std::string& path, const RunOutcome& run);
void write_pair_log(std::ostream& out, const RunOutcome& run);

// The files a run of `request` reads (lists, groundtruth.txt, every frame's images), for
// check_output_files: an output must never overwrite one of them.
std::vector<NamedPath> run_input_files(const RunRequest& request);

// What `bivo run` writes; an empty path is not written.
struct RunOutputPaths {
  std::string trajectory;            // TUM trajectory
  std::string log;                   // write_pair_log's CSV
  std::vector<std::string> configs;  // the effective configuration (experiments/tracker_config.h)
};

// The outputs as one set: all appear or, on any failure, none (and nothing is replaced).
void write_run_outputs(const RunOutcome& run, const odometry::TrackerOptions& config, const RunOutputPaths& paths);

// The backend actually used: options.backend or the method's default.
std::string effective_backend(const odometry::TrackerOptions& options);

}  // namespace bivo::experiments
