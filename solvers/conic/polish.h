#pragma once
// Active-set Newton polishing of an IPM iterate.
//
// Near the optimum the iterate tells which cone constraints are active. Per orthant entry
// and per second-order cone eigen-pair (s and z share a Jordan frame on the central path;
// the small eigenvalue of s pairs with the large one of z) the larger of the two survives,
// the same rule as s_i < z_i on the orthant (first in the iterate's units, then, if that
// guess fails and differs, with s and z each divided by its largest entry; with at most
// max_neighbour_cones second-order cones, then the guesses that differ from the first in one
// cone, boundary <-> inactive). Each cone is one of
//   inactive  : z = 0, s interior;
//   boundary  : s, z != 0 both on the boundary, z = lambda J s (J = diag(1, -I)), one
//               scalar unknown lambda and one equation psi(s) = s^T J s / 2 = 0;
//   apex      : s = 0, z free (the orthant's active entries are apex cones of size 1).
// The optimality conditions restricted to that guess,
//   c + A^T y + G^T z(x, lambda, z_apex) = 0,  A x = b,  psi_k(h - G x) = 0,  G_apex x = h_apex,
// are a small square system in (x, y, lambda, z_apex); Newton's method on it converges
// quadratically from the IPM iterate, to the solution at full precision where the IPM's
// cone-of-dimension-n+1 KKT solves stall (the paper's full form: relative gap 1e-11 but a
// step error of 1e-5). The Jacobian is symmetric,
//   [ sum_k lambda_k (Q_k - 2 g_k g_k^T)  A^T  a  G_apex^T ]
//   [ A                                   0    0  0        ]
//   [ a^T                                 0    0  0        ]
//   [ G_apex                              0    0  0        ],
// with Q_k = G_k^T G_k (formed once), g_k the head row of cone k and a_k = G_k^T J s_k.
// Newton runs in two stages. First on quadratic forms, without touching G: with s = h - G x,
//   a_k(x) = u_k + P_k x,   psi_k(x) = eta_k / 2 - u_k^T x - x^T P_k x / 2,
//   P_k = -G_k^T J G_k = Q_k - 2 g_k g_k^T,  u_k = G_k^T J h_k,  eta_k = h_k^T J h_k
// (formed once per problem: one pass over G), so a step costs O(n^2) plus the dense solve of
// the small system (Eigen LU), whatever the number of rows; a wrong guess is mostly refused
// here (a multiplier of the wrong sign, a slack outside its cone) at no cost in passes.
// Then the same Newton on the true residuals (two passes over G per evaluation) from that
// point, usually one or two steps: the quadratic forms cancel where s is small next to h.
// The polished point is a candidate only: the IPM accepts it when its own stopping test
// (residuals in original units) passes, so a wrong guess costs time, never accuracy.
// Only for problems with few variables and few apex rows (the dense system's size).
#include <limits>
#include <vector>

#include <Eigen/Core>
#include <Eigen/LU>

#include "solvers/conic/cones.h"
#include "solvers/conic/constraint_matrix.h"
#include "solvers/conic/problem_data.h"
#include "solvers/conic/variables.h"

namespace bivo::solvers::conic {

struct PolishSettings {
  int max_system_size = 200;     // n + p + boundary cones + apex rows, else no polishing
  int max_quadratic_steps = 30;  // Newton steps on the quadratic forms (no pass over G)
  int max_newton_steps = 8;      // Newton steps on the true residuals after those
  int max_neighbour_cones = 4;   // up to this many SOCs, also try the guesses one cone away
  int max_switches = 4;          // active-set switches of cones within one guess
};

class Polisher {
 public:
  Polisher(const ConicProblem& problem, const ConstraintMatrix& G, const ConeProduct& cones,
           PolishSettings settings = {});

  // Polishes the solution (x, y, z, s) / tau of iterate v; on success `out` holds a point with
  // tau = 1, kappa = 0, s and z in K, s^T z = 0 up to rounding. False when the guess gives a
  // singular system, Newton does not converge, or the result leaves K (wrong sign of a
  // multiplier: the guess was wrong), or its work would exceed `budget` (floating-point
  // operations, counted as KktSystem::work counts them: the caller bounds the polish by the
  // interior-point iterations' work).
  bool polish(const Variables& v, Variables& out, double budget = std::numeric_limits<double>::infinity());
  // The problem's data changed (same objects, new values: a solver workspace's next solve):
  // the per-problem forms are formed again on first use.
  void reset() { ready_ = false; }
  int last_newton_steps() const { return newton_steps_; }  // both stages
  int last_true_steps() const { return true_steps_; }      // the second stage's
  double last_work() const { return work_; }               // operations of the last call
  bool last_out_of_budget() const { return over_; }

 private:
  enum class Kind { kInactive, kBoundary, kApex };
  bool charge(double operations) {  // false, with nothing spent, if it would exceed the budget
    if (work_ + operations > budget_) return !(over_ = true);
    work_ += operations;
    return true;
  }
  double evaluation_work(bool quadratic) const;
  bool set_up();  // grams, head rows, u_k and eta_k, on first use; false: over budget
  // s / s_scale against z / z_scale.
  void classify(const Eigen::VectorXd& s, const Eigen::VectorXd& z, double s_scale = 1.0, double z_scale = 1.0);
  void collect();  // boundary_ and apex_rows_ from the kinds
  // Newton on the current guess, from the iterate (x, y)/tau and s0, z0 = (s, z)/tau.
  bool solve_guess(const Variables& v, const Eigen::VectorXd& s0, const Eigen::VectorXd& z0, Variables& out);
  // Residuals F at unknowns u (Newton: M du = -F) and the columns a of the boundary cones;
  // `quadratic`: from the quadratic forms, else from s = h - G x (written to s). Returns the
  // merit (largest relative violation).
  double evaluate(const Eigen::VectorXd& u, bool quadratic, Eigen::VectorXd& s, Eigen::MatrixXd& a, Eigen::VectorXd& F);
  // Newton with backtracking from u (see polish.cpp); false on a singular system.
  bool newton(Eigen::VectorXd& u, bool quadratic, int max_steps, double& merit, int& steps);
  // On the quadratic forms' solution u of the guess: false, with those cones switched, when a
  // boundary cone has a multiplier < 0 or its head <= 0 (-> inactive) or an inactive cone's
  // slack is clearly outside K (-> boundary).
  bool consistent(const Eigen::VectorXd& u);
  // u for the switched guess: x, y and z_apex kept, multipliers by least squares.
  bool relayout(Eigen::VectorXd& u);  // false: over budget

  const ConicProblem& sp_;
  const ConstraintMatrix& G_;
  const ConeProduct& cones_;
  PolishSettings settings_;
  bool ready_ = false;
  std::vector<Eigen::MatrixXd> gram_;                  // P_k = Q_k - 2 g_k g_k^T = -G_k^T J G_k, per SOC
  std::vector<Eigen::VectorXd> head_, u_;              // g_k, u_k = G_k^T J h_k
  std::vector<double> eta_;                            // h_k^T J h_k
  double norm_c_ = 1.0, norm_b_ = 1.0, norm_h_ = 1.0;  // 1 + infinity norms, for the merit
  Eigen::MatrixXd Ga_, At_;                            // apex rows of G; A^T, dense
  Eigen::VectorXd s0_, z0_;                            // the iterate's (s, z) / tau
  Eigen::VectorXd psi_scale_;                          // per boundary cone: the merit's normalization of psi
  Eigen::VectorXd s_, F_, s_trial_, F_trial_, js_;     // evaluation buffers (current point, trial)
  Eigen::MatrixXd a_, a_trial_, M_, B_;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;  // of M_, or of B_ when that is square (polish.cpp)
  bool lu_current_ = false;                  // lu_ is the current guess's (no boundary cones)
  bool lu_invertible_ = false;
  std::vector<Kind> orthant_kind_, soc_kind_;
  std::vector<int> apex_rows_;            // rows of G whose s is fixed at 0
  std::vector<int> boundary_;             // SOC indices with kind kBoundary
  std::vector<std::vector<Kind>> tried_;  // guesses tried in this polish call
  int newton_steps_ = 0, true_steps_ = 0;
  double work_ = 0.0, budget_ = 0.0, g_work_ = 0.0;  // g_work_: one product with G
  bool over_ = false;
};

}  // namespace bivo::solvers::conic
