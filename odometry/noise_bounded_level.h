#pragma once
// Method noise-bounded at one pyramid level (odometry_methods.h): the photometric solution
// x_I, the depth-residual level there, the bounded solve from x_I, the guard, and the finish
// of a relaxed level. A template over the tracker's way of running a scalarization (step or
// whole-problem backend), so it lives in a header of its own.
#include <Eigen/Core>

#include "odometry/odometry_methods.h"
#include "odometry/rgbd_problem.h"
#include "solvers/outer_loop.h"
#include "solvers/scalarization.h"
#include "solvers/summary.h"

namespace bivo::odometry {

struct NoiseBoundedLevel {
  solvers::Summary summary;  // of the bounded stage (iterations: both stages)
  double eps_bar = 0.0;      // [m^2 per unit weight]
  double rise = 0.0;         // (F_I(bounded) - F_I(x_I)) / sigma_I^2
  bool relaxed = false;
};

// Method noise-bounded at one level (odometry_methods.h): the photometric solution x_I,
// the depth-residual level there, the bounded solve from x_I, the guard, and the finish of
// x_I when the guard relaxes the bound (PolicyParameters::relaxed_tolerance).
template <class Run>
NoiseBoundedLevel solve_noise_bounded(RgbdOdometryProblem& problem, const PolicyParameters& policy, const Run& run,
                                      const solvers::SolverOptions& solver_options, Eigen::VectorXd& x) {
  NoiseBoundedLevel out;
  solvers::SolverOptions photometric_options = solver_options;
  photometric_options.keep_final_point = true;  // the bounded stage starts at x_I
  const solvers::Summary photometric = solvers::solve(problem, solvers::WeightedSum(0.0), "gn", x, photometric_options);
  const Eigen::VectorXd x_i = x;
  // The first linearization of the bounded stage is at x_I: its F_D / trace(Omega_D) is the
  // depth-residual level the bound is relative to; eps_bar is frozen there.
  RgbdOdometryProblem* p = &problem;
  double* eps_bar = &out.eps_bar;
  bool first = true;
  bool* pending = &first;
  const double ratio = policy.eps_ratio;
  out.summary = run(solvers::EpsilonConstraint([p, eps_bar, pending, ratio](const solvers::Linearization&) {
    const RgbdLinearizationStats& st = p->last_stats();
    if (*pending) {
      *eps_bar = st.weight_sum_depth > 0.0 ? ratio * st.f_depth / st.weight_sum_depth : 0.0;
      *pending = false;
    }
    return *eps_bar * st.weight_sum_depth;  // no depth residual: F_D = 0 <= 0 holds
  }));
  out.summary.iterations += photometric.iterations;
  // Guard: the rise of F_I from x_I to the bounded estimate, both under the latest weights,
  // in units of the intensity noise variance sigma_I^2 of that linearization. F_I / sigma_I^2
  // is the whitened photometric cost, so the rise is chi-square-like (6 degrees of freedom)
  // when the depth objective only moves x within the photometric noise; a biased depth image
  // moves it further, and then the photometric data reject the bound.
  const double sigma_i = problem.last_stats().sigma_intensity;
  const double f_bounded = problem.evaluate_intensity_depth(x)[0];
  const auto f_photometric = problem.evaluate_intensity_depth(x_i);
  out.rise = sigma_i > 0.0 ? (f_bounded - f_photometric[0]) / (sigma_i * sigma_i) : 0.0;
  if (!x.allFinite() || !(out.rise <= policy.guard)) {
    out.relaxed = true;
    x = x_i;
    out.summary.final_f1 = f_photometric[0];
    out.summary.final_f2 = f_photometric[1];
    // x_I was solved from an estimate the coarser, unrelaxed levels pulled towards the depth
    // objective, and the photometric solve stops at a relative decrease of 1e-3: short of the
    // optimum single reaches from its own start. Since x_I is now the answer, finish it.
    if (policy.relaxed_tolerance < solver_options.relative_decrease_tolerance) {
      solvers::SolverOptions finish = solver_options;
      finish.relative_decrease_tolerance = policy.relaxed_tolerance;
      const solvers::Summary polish = solvers::solve(problem, solvers::WeightedSum(0.0), "gn", x, finish);
      out.summary.iterations += polish.iterations;
      out.summary.final_f1 = polish.final_f1;
      out.summary.final_f2 = polish.final_f2;
    }
  }
  return out;
}

}  // namespace bivo::odometry
