#pragma once
// Where the time of a frame pair goes, per method and backend (`bivo profile`): ms per pair
// in each phase the layers record (solvers/profiling.h: pyramid, reference, residuals,
// weights, normal_equations, cone_data, subproblem, other), mean outer iterations per
// pyramid level, and per level the gap between the epsilon-constraint (QCQP / SOCP) solution
// and the Gauss-Newton single-objective solution of the same pairs:
//   F_I gap = mean over pairs of (F_I(method) - F_I(single, gn)) / F_I(single, gn)
//   F_D ratio = mean over pairs of F_D(method) / F_D(single, gn)
// i.e. what bounding F_D costs in F_I and what it buys in F_D at each level; and the runtime
// per pair of each method against single/gn, as the paper's table 3 reports it.
#include <map>
#include <string>
#include <vector>

#include "experiments/method_matrix.h"

namespace bivo::experiments {

struct ProfileRow {
  std::string method, backend;
  int pairs = 0;
  int repetitions = 0;                         // timed runs of the window
  double total_ms = 0;                         // mean per pair (over every pair of every repetition)
  double median_ms = 0, q1_ms = 0, q3_ms = 0;  // median and quartiles of the same times
  std::map<std::string, double> phase_ms;      // mean per pair
  std::vector<double> iterations_per_level;    // [level], mean over pairs (coarse levels last)
  std::vector<double> f_i_gap, f_d_ratio;      // [level] vs single/gn; empty for single itself
  std::string note;
};

struct ProfileOptions {
  std::string sequence_dir;
  // "single" with gn is the reference: moved first when listed, added first when missing.
  std::vector<MethodSpec> methods;
  odometry::TrackerOptions tracker;
  int first_frame = 0, max_frames = 30;
  // Frames for the interior-point SOCP backends (bounded:ipm-*), which cost seconds per pair
  // at VGA; 0 = max_frames. Their per-pair means are over these first frames.
  int socp_max_frames = 5;
  // After one untimed warm-up run, every method's window is timed this many times, the
  // methods' order rotated each time (no method always first), so a phase of machine load or
  // a cold cache is shared out instead of falling on one method.
  int repetitions = 3;
  int progress = -1;
};

std::vector<ProfileRow> run_profile(const ProfileOptions& options);

// profile.md / profile.csv / profile.json into dir; returns the Markdown.
std::string write_profile(const std::vector<ProfileRow>& rows, const std::string& dir);

}  // namespace bivo::experiments
