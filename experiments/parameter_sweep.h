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
  std::string epsilon_backend;            // empty: bounded's default (exact)
  int first_frame = 0, max_frames = -1;
  int progress = -1;
};

struct SweepPoint {
  std::string sequence;
  std::string parameter;  // "lambda" or "epsilon"
  double value = 0;
  double rpe_trans = 0, max_err = 0;  // RMSE and max over the 1-s windows [m/s]
  double rmse_ratio = 0, max_ratio = 0;
  double median_ms = 0;
  int failures = 0;
};

struct SweepResult {
  std::vector<SweepPoint> points;
  std::vector<std::string> notes;  // runs that failed or had no RPE (left out of points)
};

// Throws bivo::Error when a sequence has no ground truth or its single-objective run has no
// RPE (the ratios would be undefined).
SweepResult run_sweep(const SweepOptions& options);

// sweep.csv (the columns of SweepPoint), sweep.json and sweep.md into dir (atomic); returns
// the Markdown.
std::string write_sweep(const SweepResult& result, const std::string& dir);

}  // namespace bivo::experiments
