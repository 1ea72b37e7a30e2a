#pragma once
// Error vs the scalarization parameter over sequences (paper fig. 3): the method "fixed" on
// a log grid of lambda and the method "bounded" with a fixed per-unit-weight bound on a log
// grid of epsilon, each compared with the single-objective run of the same frames:
//   rmse_ratio = RPE_trans RMSE(parameter) / RPE_trans RMSE(single)
//   max_ratio  = max window error(parameter) / max window error(single)
// (< 1: the depth objective helps). Used by `bivo sweep` and `bivo report`.
#include <string>
#include <vector>

#include "odometry/tracker.h"

namespace bivo::experiments {

// n values from lo to hi evenly spaced in log10 (n >= 1; n == 1 gives lo). Throws on
// lo <= 0, hi < lo or n < 1.
std::vector<double> log_grid(double lo, double hi, int n);

struct SweepOptions {
  std::vector<std::string> sequences;
  std::vector<double> lambdas, epsilons;  // either may be empty
  odometry::TrackerOptions tracker;
  std::string epsilon_backend;  // empty: bounded's default (exact)
  int first_frame = 0, max_frames = -1;
  int progress = -1;
  double rpe_delta = 1.0;  // RPE window [s]
};

struct SweepPoint {
  std::string sequence;
  std::string parameter;  // "lambda" or "epsilon"
  double value = 0;
  double rpe_trans = 0, max_err = 0;  // RMSE and max over the RPE windows [m per window]
  double rmse_ratio = 0, max_ratio = 0;
  double median_ms = 0;
  int failures = 0;
};

struct SweepResult {
  std::vector<SweepPoint> points;
  std::vector<std::string> notes;  // runs that failed or had no RPE (left out of points)
  double rpe_delta = 1.0;          // RPE window [s] of every point
};

// One work unit of a sweep: the single-objective reference run of a sequence, or one grid
// point (method fixed at lambda = value, or bounded at eps = value).
struct SweepUnit {
  int sequence = 0;       // index into SweepOptions::sequences
  std::string parameter;  // "single", "lambda" or "epsilon"
  double value = 0;       // 0 for "single"
};

// What a unit measured. `error` is set when the run threw (or had no ground truth / no RPE);
// `missing` marks a unit that was never run (a partial merge).
struct SweepRun {
  SweepUnit unit;
  std::string sequence;  // the run's sequence name (folder name when the run failed)
  bool ok = false, missing = false;
  double rpe_trans = 0, max_err = 0, median_ms = 0;
  int failures = 0;
  std::string error;
};

// Per sequence: its reference, then every lambda, then every epsilon. Throws bivo::Error
// when there are no sequences or no grid.
std::vector<SweepUnit> sweep_units(const SweepOptions& options);
SweepRun run_sweep_unit(const SweepOptions& options, const SweepUnit& unit);

// The sweep from the runs of sweep_units(options) (same order): ratios to each sequence's
// reference; failed grid points become notes. A reference that failed (no ground truth, no
// RPE), has zero error (the ratios would be undefined) or is missing leaves its sequence's
// points out with a note; the other sequences are written.
SweepResult assemble_sweep(const SweepOptions& options, const std::vector<SweepRun>& runs);

// Every unit in one process, then assemble_sweep.
SweepResult run_sweep(const SweepOptions& options);

// sweep.csv (the columns of SweepPoint), sweep.json and sweep.md into dir (atomic); returns
// the Markdown.
std::string write_sweep(const SweepResult& result, const std::string& dir);

}  // namespace bivo::experiments
