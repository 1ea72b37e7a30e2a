#pragma once
// Frame-to-frame RGB-D odometry: coarse-to-fine estimation of T_21 for each consecutive
// pair, chained into camera-to-world poses.
//
// Usage:
//   TrackerOptions opt;                 // method "weighted", backend "" = its default
//   opt.method = "bounded";  opt.levels = 4;
//   TrackResult r = track_sequence("/data/tum/rgbd_dataset_freiburg1_rpy", opt,
//                                  [](const PairResult& p) { /* log p.iterations, p.lambda... */ });
//   io::write_tum_trajectory("estimate.txt", r.trajectory);
//
//   // One pair, one level (per-pair Pareto fronts): the problem refers into `pair`.
//   FramePair pair = load_frame_pair(seq_dir, i, i + 1, opt);
//   auto problem = pair.problem(level, opt);       // RgbdOdometryProblem
//   double lambda = pair.lambda(opt);               // what the method would use
//   io::PoseError e = io::pose_error(T_21_estimate, *pair.groundtruth_T21);
//
// Frames are streamed: a run holds only the pair it works on. A pyramid level without
// enough valid pixels is skipped (noted in LevelResult); when every level is skipped, or
// the method's lambda is undefined on the reference frame (tykkala, weighted: no valid
// depth, no texture), the pair is marked invalid and the motion prior (identity or
// constant velocity) is used. A pose is never NaN.
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "odometry/image_statistics.h"
#include "odometry/io/camera_intrinsics.h"
#include "odometry/io/pose_error.h"
#include "odometry/io/trajectory.h"
#include "odometry/io/tum_dataset.h"
#include "odometry/odometry_methods.h"
#include "odometry/rgbd_problem.h"
#include "odometry/rgbd_pyramid.h"
#include "solvers/geometry/se3.h"
#include "solvers/profiling.h"

namespace bivo::odometry {

enum class InitialGuess { kIdentity, kConstantVelocity };
InitialGuess parse_initial_guess(const std::string& name);  // "identity" | "constant-velocity"
const char* to_string(InitialGuess guess);

// The problem options a tracker starts from: RgbdProblemOptions' defaults with the Jacobian
// kind, the depth noise exponent and the affine brightness left to the method ("auto").
inline RgbdProblemOptions method_default_problem() {
  RgbdProblemOptions o;
  o.jacobian = JacobianKind::kMethodDefault;
  o.depth_noise_exponent = -1;
  o.affine_brightness = -1;
  return o;
}

struct TrackerOptions {
  std::string method = "weighted";  // single, depth, fixed, tykkala, weighted, bounded, joint, scaled, noise-bounded
  std::string backend;              // empty: default_backend(method) (gn / exact)
  PolicyParameters policy;          // lambda (fixed), phi, delta, eps_min/eps_max/eps (bounded)
  int levels = 4;                   // 640x480 .. 80x60
  int finest_level = 0;             // stop refining at this level (0 = full resolution)
  InitialGuess initial_guess = InitialGuess::kConstantVelocity;
  // 1: a pair that no level could solve from a constant-velocity prior is estimated again from
  // rest (the identity) before it takes the prior (estimate_motion_from_prior): a velocity
  // estimated wrong once otherwise repeats itself, each next pair starting from it, failing
  // and being chained with it. 0: the prior stands.
  int retry_from_rest = 1;
  int max_iterations = 20;                    // per pyramid level
  double step_tolerance = 1e-4;               // |delta| (m, rad) that ends a level
  double relative_decrease_tolerance = 1e-3;  // relative merit change that ends a level
                                              // (joint: PolicyParameters::joint_tolerance)
  // A step that would move the reference points' projections by less than this RMS image
  // motion (pixels of the level being solved) is not taken and ends the level (0: off, the
  // default: at 0.05 px it cut iterations by 40 % but raised weighted's RPE on fr1/rpy by 5 %
  // and stalled depth-heavy methods on slow fr3/office motion; docs/odometry.md "Speed").
  double pixel_motion_tolerance = 0.0;
  // Largest factor a crawling Gauss-Newton step may be extrapolated by
  // (solvers::SolverOptions::max_step_extrapolation; 1 = off; -1, the default: the method's
  // own, method_step_extrapolation(): on for robust only, since for the other methods it cut
  // iterations but moved the synthetic scenes' RPE by more than 2 %; docs/results/speed.md).
  double step_extrapolation = -1.0;
  // With reference-side gradients (Jacobian inverse or esm: joint's default) the Gauss-Newton
  // fixed point is that of an approximate Jacobian, not the cost's stationary point; N > 0
  // continues the finest level from there with current-side (exact) gradients for at most N
  // more iterations (0: off; no effect with forward Jacobians). On by default: it took joint's worst RPE ratio to
  // single from 1.37 to 1.09 over the nine sequences (docs/odometry.md, "exact finish").
  int exact_finish_iterations = 20;
  // Unsynchronized colour and depth (the frames' depth.txt times differ from their rgb.txt
  // times): 1 estimates the pair, moves both depth images to their colour images' times by the
  // velocity there (PreparedFrame::arrival_velocity; depth_retiming.h) and estimates again; 0 (the
  // default) takes each depth image as taken with its colour image. No effect on synchronized
  // frames. Off by default: held out it ties joint's worst ratio at 2.2-2.9x its CPU per pair
  // (docs/results/defaults.md).
  int retime_depth = 0;
  // Rolling shutter: the colour images' rows are read over this many seconds (the timestamp is
  // the middle row's); > 0 estimates the pair, moves both colour images to their timestamps by
  // the velocity there (PreparedFrame::arrival_velocity; rolling_shutter.h), unsynchronized depth there
  // too (as retime_depth 1: colour moved beside depth left at its own time drew joint to 4.7 deg
  // on a fast rendering's pair, 1.1 with both moved), and estimates again from it; 0:
  // global-shutter images. -1 (the default): the readout the sequence states (a bivo synth
  // rendering's scene.json, io/sensor_description.h), else 0; a pair estimated alone (no
  // sequence) takes -1 as 0. A property of the sensor, not tuned.
  double readout_time = -1.0;
  // Vignetting: the colour images' fall-off 1 - k rho^2 (io/vignetting.h) divided out of
  // every frame before tracking, and joint's brightness model left without its own fall-off
  // term (method_affine_brightness()). -1 (the default): the fall-off the sequence states (a
  // bivo synth rendering's scene.json), else 0 (none divided out: real TUM sequences state
  // none; joint then fits the fall-off per pair). A property of the sensor, not tuned.
  double vignetting = -1.0;
  // With frames corrected (readout_time > 0 or retime_depth 1 on unsynchronized depth): how
  // many times the pair is estimated again on frames corrected with its latest estimate's
  // velocity (1: once, from the estimate on the frames as given). The correction moves each
  // row and depth pixel by a velocity that was itself estimated on uncorrected frames; each
  // round brings it closer to the velocity its own frames imply. -1 (the default): the method's
  // own, method_correction_rounds().
  int correction_rounds = -1;
  // single / depth optimize one objective and build only its model per iteration; true
  // also evaluates the other one (weights estimated at the level's final x) for the logs,
  // LevelResult::f_i / f_d and PairResult::f_i / f_d, which are NaN otherwise.
  bool evaluate_unused_objective = false;
  int min_valid_pixels = 200;                             // fewer valid terms at a level: the level is skipped
  RgbdProblemOptions problem = method_default_problem();  // weights (tdist/huber/none, nu), depth
                                                          // range, occlusion, Jacobian kind ("auto": the method's own,
                                                          // method_jacobian()), threads (also those of the pyramid)
  double max_association_dt = 0.02;                       // seconds
  std::optional<io::Intrinsics> intrinsics;               // override of the sequence-name preset
  // Lens distortion of the stored images (override of the sequence-name preset, io/lens_distortion.h);
  // frames are undistorted once, at loading, when it is not the identity.
  std::optional<io::Distortion> distortion;
  int first_frame = 0;               // index of the first associated frame processed
  int max_frames = -1;               // frames processed from first_frame (-1: to the end)
  bool start_at_groundtruth = true;  // first pose from groundtruth.txt when it covers frame 0
  // track_sequence loads (decodes, undistorts) the next frame on a thread of its own while it
  // tracks a pair (io/frame_stream.h): the same results, a fr1/rpy run at one thread in 0.64x
  // (640x480) / 0.82x (320x240) the wall time. A pair's CPU time excludes the loader's, but
  // the decoder's memory traffic adds ~3-4 % to it at 320x240, and with threads >= 2 the
  // loader takes turns with the per-pixel workers on the cores. false: frames load between pairs, on the calling
  // thread.
  bool prefetch_frames = true;
  // With prefetch_frames: loader threads, each decoding a frame of its own, so up to this many
  // frames ahead. One decoder cannot keep up with the tracker on TUM's PNGs (~17 ms per
  // 640x480 frame against ~12 ms per pair at 640x480 and ~4.5 ms at 320x240): two finish a
  // run sooner, but where they share the cores with the tracker they stretch every pair's
  // wall time, which `bivo profile` and the runtime tables report (docs/faq.md). 0 = auto: two when the processors this
  // process may run on have a core for each beside the per-pixel threads, else one (load_threads_for()). Results do not
  // depend on it.
  int load_threads = 0;
  int verbosity = 0;  // passed to the solver
};

// The loader threads `options` asks for: load_threads, or for 0 two when `cores` (0: the
// processors this process may run on) leave a core for each beside problem.threads, else
// one; 0 without prefetch_frames.
int load_threads_for(const TrackerOptions& options, unsigned cores = 0);

// The backend the options name, or the method's default (gn / exact) when none is named.
std::string tracker_backend(const TrackerOptions& options);
// The problem options the tracker solves `method` with: the method's own settings and "auto"
// values resolved (the Jacobian kind, which depends on the level, aside).
RgbdProblemOptions method_problem_options(Method method, const TrackerOptions& options);
// Checks names and numbers up front (unknown method/backend, backend that cannot solve the
// method's scalarization, levels < 1, ...); throws bivo::Error listing valid choices.
void validate(const TrackerOptions& options);

struct LevelResult {
  int level = 0;
  int terms = 0;                             // reference pixels with valid depth
  int valid_intensity = 0, valid_depth = 0;  // at the final x of the level
  int iterations = 0;
  bool skipped = false;         // too few valid pixels: x left unchanged
  double f_i = 0.0, f_d = 0.0;  // final objectives (weights of the last linearization; the
                                // objective single / depth do not optimize: NaN unless
                                // TrackerOptions::evaluate_unused_objective)
  double lambda = 0.0;          // weighted sum: lambda used (joint, scaled: at the last step)
  double correlation = 0.0;     // joint: rho = S_ID / sqrt(S_II S_DD) at the last linearization
  bool relaxed = false;         // noise-bounded: the guard relaxed the bound (x_I kept)
  bool kept_prior = false;      // joint, robust with both starts: the estimate from the prior was kept
  double trust = 0.0;           // robust: the depth trust statistic T at the level's bi-objective estimate
                                // (depth_trust.h; relaxed: T exceeded the threshold, F_I alone solved;
                                // NaN: the test is off, PolicyParameters::trust)
  double guard_rise = 0.0;      // noise-bounded: (F_I(bounded) - F_I(x_I)) / sigma_I^2, the guard's statistic
  double epsilon = 0.0;         // bounded: epsilon bound on F_D at the last step
  double mu = 0.0;              // bounded: multiplier of the last step (+inf: infeasible)
  std::string termination;
};

struct PairResult {
  int index = 0;  // pair k: frames k (reference) and k + 1 (current)
  double t_reference = 0.0, t_current = 0.0;
  Eigen::Isometry3d T_21 = Eigen::Isometry3d::Identity();  // estimated motion
  Eigen::Isometry3d T_wc = Eigen::Isometry3d::Identity();  // pose of the current frame
  bool valid = true;                                       // false: every level skipped, T_21 = motion prior
  std::string note;                                        // why a level or the pair was degraded
  int iterations = 0;                                      // outer iterations over all levels
  double lambda = 0.0, epsilon = 0.0, mu = 0.0;            // at the finest level solved (joint: implied lambda)
  double correlation = 0.0;                                // joint: rho of S at the finest level solved
  int relaxed_levels = 0;                                  // noise-bounded: levels whose bound the guard relaxed;
                                                           // robust: levels solved on F_I alone (depth distrusted)
  double trust = 0.0;                                      // robust: trust statistic at the finest level solved
  double epsilon_per_weight = 0.0;                         // bounded: eps_bar [m^2]
  double f_i = 0.0, f_d = 0.0;                             // at the finest level solved
  double seconds = 0.0;                                    // track_sequence: the estimation and a frame's pyramid
                                                           // + statistics (no PNG decoding), wall. The frame is the
                                                           // pair's current one with one thread; with more, the
                                                           // next pair's, prepared beside the estimation (the
                                                           // first pair: both)
  double cpu_seconds = 0.0;                                // the same span in CPU time: of the process (all
                                                           // threads) less the frame loaders' (prefetch_frames)
  double load_seconds = 0.0;                               // wall time spent waiting, before the estimation, for
                                                           // the frame prepared in `seconds` to load (PNG decoding,
                                                           // undistortion): all of it without
                                                           // TrackerOptions::prefetch_frames, the part the
                                                           // loader threads had not finished with it
  solvers::PhaseProfile profile;                           // "pyramid", "residuals", "weights", "normal_equations", ...
  std::vector<LevelResult> levels;                         // coarse to fine
  std::optional<io::PoseError> error;                      // against ground truth, when available
};

struct TrackResult {
  std::string sequence;
  io::Intrinsics intrinsics;
  double readout_time = 0.0;  // the rolling-shutter readout used (TrackerOptions::readout_time)
  double vignetting = 0.0;    // the fall-off divided out (TrackerOptions::vignetting)
  io::Trajectory trajectory;  // one pose per frame, T_wc
  std::vector<PairResult> pairs;
  solvers::PhaseProfile profile;  // summed over pairs (plus the first frame's pyramid)
  int invalid_pairs = 0;
  double load_seconds = 0.0;  // waits for loading, all frames (not part of any pair)
};

// The frames [begin, end) of a sequence of `total` frames that options.first_frame and
// max_frames select; bivo::Error naming `directory` and `total` when fewer than 2 remain.
struct FrameWindow {
  int begin = 0, end = 0;
};
FrameWindow frame_window(int total, const TrackerOptions& options, const std::string& directory);

// How the tracker opens a sequence: association window, intrinsics and distortion overrides.
io::SequenceOptions sequence_options(const TrackerOptions& options);
// The options with readout_time and vignetting -1 replaced by what the sequence states (else 0).
TrackerOptions with_stated_sensor(TrackerOptions options, std::optional<double> readout,
                                  std::optional<double> vignetting);

// Streams frames first_frame .. first_frame + max_frames - 1 of the sequence in `directory`,
// calling on_pair after each pair. Throws bivo::Error when the window holds fewer than 2
// frames (naming the sequence's frame count). With problem.threads >= 2 the next pair's
// current frame is prepared (pyramid, statistics) on a worker while a pair is estimated
// (sequence_tracking.h); results do not depend on it.
TrackResult track_sequence(const std::string& directory, const TrackerOptions& options,
                           const std::function<void(const PairResult&)>& on_pair = {});
// The same on a sequence already opened with sequence_options(options).
TrackResult track_sequence(const io::TumSequence& sequence, const TrackerOptions& options,
                           const std::function<void(const PairResult&)>& on_pair = {});

// One preprocessed frame: its pyramid and full-resolution statistics (without the medians,
// which estimate_motion() and FramePair::lambda() add when the method reads them). An rvalue
// image is moved into the pyramid; levels finer than finest_level are not interleaved
// (build_pyramid).
struct PreparedFrame {
  RgbdPyramid pyramid;
  // Of level 0, when has_statistics. prepare_frame() computes them when asked; a method's
  // rule that reads them (reads_frame_statistics()) computes them itself when they are absent.
  FrameStatistics statistics;
  bool has_statistics = false;
  // The pair that ended at this frame, once estimated (track_sequence sets it): its motion
  // log(T_21) per second and its middle time. Retiming and the rolling-shutter model take the
  // velocity at each frame's time as linear through it and the next pair's; without it, the
  // next pair's alone (constant velocity left joint's 1-s RPE on the fast renderings 1.4-2.9x higher).
  std::optional<solvers::se3::Vector6d> arrival_velocity;
  double arrival_time = 0.0;
};
// with_statistics false: the frame statistics are left out (~0.3 ms per 640x480 frame) for
// methods whose rule does not read them (all but weighted and bounded: reads_frame_statistics()).
PreparedFrame prepare_frame(io::RgbdImage image, const io::Intrinsics& K, int levels, int threads = 1,
                            int finest_level = 0, bool with_statistics = true);

// CPU time of this process so far (every thread), seconds.
double process_cpu_seconds();
// CPU time of the calling thread so far, seconds.
double thread_cpu_seconds();

// Estimates T_21 from reference to current starting at `initial` (coarse to fine). The
// result's timing fields cover the estimation only.
PairResult estimate_motion(const PreparedFrame& reference, const PreparedFrame& current,
                           const Eigen::Isometry3d& initial, const TrackerOptions& options);

// estimate_motion() from a motion prior; with TrackerOptions::retry_from_rest, a pair that no
// level could solve from a prior other than the identity is estimated again from rest; that
// estimate replaces the prior when its residuals (r_I; r_D for depth) at the finest level have
// a t-scale no larger than the prior's, else the prior stands (iterations and times count both
// solves, the CPU time also the comparison). track_sequence() estimates every pair so.
PairResult estimate_motion_from_prior(const PreparedFrame& reference, const PreparedFrame& current,
                                      const Eigen::Isometry3d& prior, const TrackerOptions& options);

// Two frames of a sequence for per-pair studies (Pareto fronts, unit tests).
struct FramePair {
  std::string sequence;
  io::AssociatedFrame reference_frame, current_frame;
  PreparedFrame reference, current;
  std::optional<Eigen::Isometry3d> groundtruth_T21;
  std::optional<double> readout_time;  // as the sequence states it (io::TumSequence)
  double vignetting = 0.0;             // the fall-off divided out of both frames (TrackerOptions::vignetting)

  // The odometry problem at one level with the options' problem settings (depth_first is
  // set for method "depth"), on the frames as loaded (TrackerOptions::retime_depth is not
  // applied: it needs the pair's estimate). The problem refers into this FramePair.
  std::unique_ptr<RgbdOdometryProblem> problem(int level, const TrackerOptions& options) const;
  // The options with the vignetting the frames were loaded with (their fall-off is already
  // divided out): what estimate_motion() on this pair's frames must be given.
  TrackerOptions as_loaded(TrackerOptions options) const {
    options.vignetting = vignetting;
    return options;
  }
  // lambda of a weighted-sum method / eps_bar of bounded, as the tracker would choose them.
  double lambda(const TrackerOptions& options) const;
  double epsilon_per_weight(const TrackerOptions& options) const;
};
FramePair load_frame_pair(const std::string& directory, int reference_index, int current_index,
                          const TrackerOptions& options);

}  // namespace bivo::odometry
