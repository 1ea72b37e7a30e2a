#pragma once
// Method robust at one pyramid level (odometry_methods.h): joint's weighted sum, the exact
// finish at the finest level, then the depth trust test (depth_trust.h) at the estimate; when
// the photometric data reject it, the level is solved again on F_I alone from there. A
// template over the tracker's way of running a scalarization, as noise_bounded_level.h.
#include <algorithm>
#include <limits>

#include <Eigen/Core>

#include "odometry/depth_trust.h"
#include "odometry/odometry_methods.h"
#include "odometry/rgbd_problem.h"
#include "solvers/outer_loop.h"
#include "solvers/scalarization.h"
#include "solvers/summary.h"

namespace bivo::odometry {

struct RobustLevel {
  solvers::Summary summary;  // of the last stage (iterations: all stages)
  double lambda = 0.0;       // joint's implied lambda at its last step
  double statistic = 0.0;    // the trust statistic T at the bi-objective estimate (NaN: test off)
  bool distrusted = false;   // T > trust: the level ended on F_I alone
};

// `exact_finish`: iterations of the exact (current-side) continuation of the bi-objective
// solve when the problem uses reference-side gradients (0: none; the tracker passes it at
// the finest level only). `solver_options.relative_decrease_tolerance` ends every stage.
template <class Run>
RobustLevel solve_robust_level(RgbdOdometryProblem& problem, const PolicyParameters& policy, const Run& run,
                               solvers::SolverOptions solver_options, int exact_finish, Eigen::VectorXd& x) {
  RobustLevel out;
  RgbdOdometryProblem* p = &problem;
  const PolicyParameters pol = policy;
  double* last = &out.lambda;
  const solvers::WeightedSum joint([p, pol, last](const solvers::Linearization&) {
    return *last = residual_lambda(Method::kRobust, p->last_stats(), pol);
  });
  out.summary = run(joint, solver_options);
  int iterations = out.summary.iterations;
  const bool reference_side = problem.options().jacobian != JacobianKind::kForward;
  if (reference_side) problem.set_jacobian(JacobianKind::kForward);  // the test needs the exact gradient
  if (exact_finish > 0 && reference_side && x.allFinite()) {
    solvers::SolverOptions finish = solver_options;
    finish.max_iterations = std::min(solver_options.max_iterations, exact_finish);
    out.summary = run(joint, finish);
    iterations += out.summary.iterations;
  }
  // T costs a linearization with exact gradients: evaluated only when the test is on.
  if (!x.allFinite() || !trust_test_on(policy)) {
    out.statistic = std::numeric_limits<double>::quiet_NaN();
    out.summary.iterations = iterations;
    return out;
  }
  solvers::LinearizeOptions lo;
  lo.profile = solver_options.profile;
  const solvers::Linearization at = problem.linearize(x, lo);
  out.statistic = photometric_distance(at.f1, problem.last_stats().sigma_intensity).statistic;
  if (out.statistic > policy.trust) {
    out.distrusted = true;
    problem.set_objectives(false, false);
    out.summary = run(solvers::WeightedSum(0.0), solver_options);
    iterations += out.summary.iterations;
  }
  out.summary.iterations = iterations;
  return out;
}

}  // namespace bivo::odometry
