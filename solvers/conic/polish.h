#pragma once
// Active-set Newton polishing of an IPM iterate.
//
// Near the optimum the iterate tells which cone constraints are active. Per orthant entry
// and per second-order cone eigen-pair (s and z share a Jordan frame on the central path;
// the small eigenvalue of s pairs with the large one of z) the larger of the two survives,
// the same rule as s_i < z_i on the orthant (first in the iterate's units, then, if that
// guess fails and differs, with s and z each divided by its largest entry). Each cone is one of
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
// with Q_k = G_k^T G_k (formed once), g_k the head row of cone k and a_k = G_k^T J s_k, so a
// Newton step costs two passes over G plus a dense solve of the small system (Eigen LU).
// The polished point is a candidate only: the IPM accepts it when its own stopping test
// (residuals in original units) passes, so a wrong guess costs time, never accuracy.
// Only for problems with few variables and few apex rows (the dense system's size).
#include <vector>

#include <Eigen/Core>

#include "solvers/conic/cones.h"
#include "solvers/conic/constraint_matrix.h"
#include "solvers/conic/problem_data.h"
#include "solvers/conic/variables.h"

namespace bivo::solvers::conic {

struct PolishSettings {
  int max_system_size = 200;  // n + p + boundary cones + apex rows, else no polishing
  int max_newton_steps = 8;
};

class Polisher {
 public:
  Polisher(const ConicProblem& problem, const ConstraintMatrix& G, const ConeProduct& cones,
           PolishSettings settings = {});

  // Polishes the solution (x, y, z, s) / tau of iterate v; on success `out` holds a point with
  // tau = 1, kappa = 0, s and z in K, s^T z = 0 up to rounding. False when the guess gives a
  // singular system, Newton does not converge, or the result leaves K (wrong sign of a
  // multiplier: the guess was wrong).
  bool polish(const Variables& v, Variables& out);
  int last_newton_steps() const { return newton_steps_; }

 private:
  enum class Kind { kInactive, kBoundary, kApex };
  void set_up();  // grams and head rows, on first use
  void classify(const Eigen::VectorXd& s, const Eigen::VectorXd& z);
  // Newton on the current guess, from the iterate (x, y)/tau and s0, z0 = (s, z)/tau.
  bool solve_guess(const Variables& v, const Eigen::VectorXd& s0, const Eigen::VectorXd& z0, Variables& out);

  const ConicProblem& sp_;
  const ConstraintMatrix& G_;
  const ConeProduct& cones_;
  PolishSettings settings_;
  bool ready_ = false;
  std::vector<Eigen::MatrixXd> gram_;       // Q_k - 2 g_k g_k^T = -G_k^T J G_k, per SOC
  std::vector<Kind> orthant_kind_, soc_kind_;
  std::vector<int> apex_rows_;              // rows of G whose s is fixed at 0
  std::vector<int> boundary_;               // SOC indices with kind kBoundary
  int newton_steps_ = 0;
};

}  // namespace bivo::solvers::conic
