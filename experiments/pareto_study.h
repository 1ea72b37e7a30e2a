#pragma once
// The Pareto front (F_I, F_D) of one frame pair at one pyramid level, traced by a lambda
// sweep and by an epsilon sweep (solvers/pareto.h), with the point each odometry method picks
// on the same pair, the knee, and every point's pose error against ground truth when known.
// Used by `bivo pareto` and `bivo report`.
//
// Every point's objectives are re-evaluated the same way, F_I and F_D at x with the robust
// weights estimated at x, so points from different sweeps and methods are comparable.
#include <optional>
#include <string>
#include <vector>

#include "odometry/tracker.h"
#include "solvers/pareto.h"

namespace bivo::experiments {

struct ParetoStudyOptions {
  std::string sequence_dir;
  int pair = 0;     // reference frame index; current = pair + 1
  int level = 1;    // pyramid level of the problem (0 = full resolution)
  int points = 15;  // per sweep
  double lambda_min = 1.0, lambda_max = 1e7;
  std::vector<std::string> methods{"single", "depth", "tykkala", "weighted", "bounded"};
  odometry::TrackerOptions tracker;  // levels, policy parameters, weights
  // Solver backend of the sweeps it can solve (solvers/backend_registry.h): a weighted-sum one
  // replaces gn in the lambda sweep, an epsilon-constraint one exact in the epsilon sweep, one
  // that does both replaces both; empty: gn and exact. So fronts compare across backends.
  std::string backend;
};

// Throws bivo::Error when a backend is given that solves neither sweep, or points is not in 2..1000.
void check_pareto_study_options(const ParetoStudyOptions& options);

struct StudyPoint {
  double f_i = 0, f_d = 0;
  double parameter = 0;  // lambda or epsilon
  std::string method;    // for method picks
  Eigen::Isometry3d T_21 = Eigen::Isometry3d::Identity();
  std::optional<odometry::io::PoseError> error;
};

struct ParetoStudy {
  std::string sequence;
  int pair = 0, level = 0;
  double t_reference = 0, t_current = 0;
  std::vector<StudyPoint> lambda_front, epsilon_front, methods;  // fronts: non-dominated
  std::optional<StudyPoint> knee;  // of the union of both fronts (normalized distance to chord)
  double seconds = 0;
};

ParetoStudy run_pareto_study(const ParetoStudyOptions& options);

// The JSON read by plots/pareto_front.py.
std::string pareto_json(const ParetoStudy& study);

// The pairs of `bivo pareto`: {pair} when pair >= 0, else 0, every, 2 every, ... (at most
// max_pairs, each with a following frame). Throws bivo::Error when neither is given.
std::vector<int> pareto_pairs(const std::string& sequence_dir, int pair, int every, int max_pairs);

// Writes the studies of the pairs (one work unit each, run by run_pareto_study) into `dir`
// (created): pareto_pair<K>.json (+ .png when `plots`) and pareto.md, atomically; `methods`
// are the columns of the methods' errors. Returns the Markdown.
std::string write_pareto_studies(const std::vector<ParetoStudy>& studies, const std::vector<std::string>& methods,
                                 const std::string& dir, bool plots);

}  // namespace bivo::experiments
