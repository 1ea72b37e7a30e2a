#pragma once
// Primal-dual interior-point method for the conic program of problem_data.h over
// K = orthant x second-order cones (an ECOS-like design, written from the published
// algorithms: Vandenberghe's CVXOPT cone program notes, Domahidi et al. ECC 2013):
//   * homogeneous self-dual embedding (tau, kappa): infeasibility and unboundedness are
//     certified instead of diverging;
//   * Nesterov-Todd scaling, Mehrotra predictor-corrector with sigma = (1 - alpha_aff)^3;
//   * sparse quasi-definite KKT system (kkt_system.h): O(n) nonzeros per cone of dimension n;
//   * Ruiz equilibration (problem_data.h), stopping tests in the original units.
// Exit flags: see IpmStatus. The solver never returns NaN: a NaN or failed factorization
// ends with kNumericalTrouble and the last finite iterate.
#include <iosfwd>
#include <limits>
#include <memory>
#include <string>

#include <Eigen/Core>

#include "solvers/conic/ipm_timings.h"
#include "solvers/conic/problem_data.h"

namespace bivo::solvers::conic {

enum class IpmStatus { kOptimal, kPrimalInfeasible, kDualInfeasible, kMaxIterations, kNumericalTrouble };
std::string to_string(IpmStatus status);

struct IpmSettings {
  double feastol = 1e-8;  // primal/dual residual, relative
  double abstol = 1e-8;   // absolute duality gap s^T z
  double reltol = 1e-8;   // relative duality gap
  // Relative objective gap |c'x + b'y + h'z| / (1 + |c'x|) (certificate.h): the test that a
  // point feasible only relative to a huge ||h|| cannot pass.
  double gaptol = 1e-8;
  // Reduced-accuracy tolerances (ECOS's "inaccurate" exits): used only when the iteration
  // stalls (numerical trouble, iteration limit); the result then has reduced_accuracy set.
  double feastol_inaccurate = 1e-4;
  double abstol_inaccurate = 5e-5;
  double reltol_inaccurate = 5e-5;
  double gaptol_inaccurate = 5e-5;
  // Bounds at or beyond this are absent, as modelling tools write them (1e20, 1e30): an
  // orthant row with h >= infinity and a second-order cone whose head h >= infinity (its tail
  // finite) are removed before the solve and restored in the result (z = 0, s = h - G x).
  // Rows with h <= -infinity and equalities are real constraints and are kept.
  // +infinity = no presolve.
  double infinity = 1e20;
  int max_iterations = 100;
  int equilibration_passes = 12;  // 0 = off
  double step_fraction = 0.99;    // of the distance to the boundary
  double static_regularization = 1e-8;
  int max_refinement_steps = 5;
  // Active-set Newton polishing (polish.h), tried at every iteration once the residuals and
  // the (absolute or relative) gap are below polish_from; a polished point is returned only
  // when it meets the tolerances above, else the iterations go on. A failed try costs little
  // (Newton on quadratic forms first, polish.h), so by default it is tried from the start
  // (the iterate after initialization).
  bool polish = true;
  double polish_from = std::numeric_limits<double>::infinity();
  // Refined KKT solves check against the unexpanded system (passes over G) once the best
  // iterate's residuals and gap are below this; before, refinement runs on the reduced system.
  double full_refinement_from = 1e-4;
  std::ostream* log = nullptr;  // per-iteration log when set
  // Seconds by phase in IpmResult::timings (the counters are kept either way); off, only
  // the total and the polish are timed.
  bool time_phases = false;
};

struct IpmResult {
  IpmStatus status = IpmStatus::kNumericalTrouble;
  // Every verdict is certified from these vectors (certificate.h); a point that fails is not
  // returned as optimal. Optimal: the solution. Primal infeasible: (y, z) a certificate with h^T z + b^T y = -1.
  // Dual infeasible: (x, s) a certificate with c^T x = -1. Other: the last iterate / tau.
  Eigen::VectorXd x, y, z, s;
  double primal_objective = 0.0, dual_objective = 0.0;
  // Measured on the returned (x, y, z, s) and the given data, unscaled (certificate.h),
  // after any rows treated as infinite are set aside (their z = 0, s = h - G x).
  double primal_residual = 0.0, dual_residual = 0.0, gap = 0.0, relative_gap = 0.0;
  double objective_gap = 0.0;     // |c'x + b'y + h'z| / (1 + |c'x|)
  int infinite_rows = 0;          // rows of G removed as infinite bounds (IpmSettings::infinity)
  bool reduced_accuracy = false;  // met only the *_inaccurate tolerances; `note` says which
                                  // strict tolerance failed and whether it is below what
                                  // double precision can resolve (its rounding floor)
  double primal_residual_floor = 0.0, dual_residual_floor = 0.0;  // set with reduced_accuracy
  std::string note;
  bool polished = false;        // the solution is the polished point (polish.h) ...
  int polish_newton_steps = 0;  // ... after this many Newton steps
  int iterations = 0;
  double seconds = 0.0;
  IpmTimings timings;  // seconds by phase (with time_phases: they sum to `seconds`) and counts
  long kkt_factor_nonzeros = 0;
};

// Validates the problem (bivo::Error on bad input), then solves it.
IpmResult solve_conic(const ConicProblem& problem, const IpmSettings& settings = {});

// The solver's buffers (the scaled copy of G, the KKT system, the iterates and every
// per-iteration vector), kept from one solve to the next. A caller that solves problems of
// one size again and again (a step backend, once per outer iteration) passes the same
// workspace, so a solve neither allocates nor touches fresh memory: at n = 2e4 the page
// faults on freshly allocated O(n) buffers were half the CPU time of a solve. Results are
// identical to solve_conic without a workspace. Not for two threads at once.
class IpmWorkspace {
 public:
  IpmWorkspace();
  ~IpmWorkspace();
  IpmWorkspace(IpmWorkspace&&) noexcept;
  IpmWorkspace& operator=(IpmWorkspace&&) noexcept;
  struct State;

 private:
  std::unique_ptr<State> state_;
  friend const IpmResult& solve_conic(const ConicProblem&, const IpmSettings&, IpmWorkspace&);
};

// As above, in the workspace's buffers; the result lives in the workspace until its next solve.
const IpmResult& solve_conic(const ConicProblem& problem, const IpmSettings& settings, IpmWorkspace& workspace);

// The exit in words: "optimal", "optimal (reduced accuracy: ...)", "primal infeasible", ...
std::string status_text(const IpmResult& result);

}  // namespace bivo::solvers::conic
