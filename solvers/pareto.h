#pragma once
// Pareto fronts of a BiObjectiveProblem by sweeping a scalarization's parameter.
//   sweep_lambda:  lambda on a log grid [lambda_min, lambda_max] (weighted sum; only the
//                  convex part of a front is reachable this way);
//   sweep_epsilon: epsilon on a uniform grid over [min F_2, F_2 at the F_1-minimizer]
//                  (epsilon-constraint; reaches non-convex parts too).
// Each point is warm-started where its neighbour last linearized, and takes its first step
// from that linearization (LinearizationCarry, solvers/outer_loop.h); sweep_lambda may start
// it from a secant prediction instead (ParetoOptions::secant_predictor). Dominated points are dropped;
// the survivors are sorted by F_1 ascending (so F_2 descending).
//
// Knee: the point farthest from the chord between the two extreme points, measured in
// NORMALIZED objective space f^_j = (f_j - min_front f_j) / (max_front f_j - min_front f_j),
// so the two objectives' units (intensity^2 vs metres^2) do not decide the knee.
// Hypervolume: area dominated by the front and bounded by a reference point (raw units).
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "solvers/problem.h"
#include "solvers/summary.h"

namespace bivo::solvers {

struct ParetoPoint {
  double f1 = 0.0, f2 = 0.0;
  Eigen::VectorXd x;
  ScalarizationKind kind = ScalarizationKind::kWeightedSum;
  double parameter = 0.0;   // lambda (weighted sum) or epsilon (epsilon-constraint)
  double multiplier = 0.0;  // lambda or the final step's mu
  int iterations = 0;
  bool converged = false;
  bool feasible = true;
};

struct ParetoOptions {
  int points = 21;                             // >= 2
  double lambda_min = 1e-3, lambda_max = 1e3;  // sweep_lambda only; 0 < min < max
  std::string backend;                         // empty: "gn" for lambda, "exact" for epsilon
  SolverOptions solver;
  // sweep_lambda: where the front moves fast, start a point from the secant prediction
  // x_k (+) (x_k (-) x_{k-1}) of the two previous (converged) points instead of from x_k:
  // used when |x_k (-) x_{k-1}| > 2 solver.step_tolerance (a point that moved less is about
  // one small step from the next one and gains nothing from a prediction, whose first
  // linearization would need a new residual pass). Each point is still a solve of its own
  // weighted sum to the same tolerances; only its starting point differs. With a robust
  // (IRLS) problem, whose iterations contract linearly, it took the level-0 sweep of
  // fr1/desk from 58 to 43 iterations.
  bool secant_predictor = true;
};

struct ParetoFront {
  std::vector<ParetoPoint> points;  // non-dominated, sorted by f1 ascending
  std::vector<ParetoPoint> all;     // every solved point in sweep order
  int dropped = 0;                  // all.size() - points.size()
  double f2_min = 0.0;              // sweep_epsilon: the range swept
  double f2_at_f1_min = 0.0;
};

ParetoFront sweep_lambda(BiObjectiveProblem& problem, const Eigen::VectorXd& x0, const ParetoOptions& options = {});
// sweep_lambda's range check, for callers that check options before any work: throws
// bivo::Error unless 0 < lambda_min < lambda_max < inf.
void check_lambda_range(double lambda_min, double lambda_max);
ParetoFront sweep_epsilon(BiObjectiveProblem& problem, const Eigen::VectorXd& x0, const ParetoOptions& options = {});

// a dominates b: a is no worse in both objectives and strictly better in one.
bool dominates(const ParetoPoint& a, const ParetoPoint& b);
// The non-dominated points (exact duplicates kept once), sorted by f1 ascending.
std::vector<ParetoPoint> nondominated(const std::vector<ParetoPoint>& points);
// Index into `front` (non-dominated, sorted by f1) of the knee; nullopt with < 3 points
// or a degenerate front (zero range in an objective).
std::optional<std::size_t> knee_index(const std::vector<ParetoPoint>& front);
// Area dominated by `points` inside the box up to (ref_f1, ref_f2); points outside count 0.
double hypervolume(const std::vector<ParetoPoint>& points, double ref_f1, double ref_f2);

}  // namespace bivo::solvers
