#pragma once
// The Newton system of the conic IPM,
//     [ 0  A^T  G^T  ] [dx]   [rx]
//     [ A  0    0    ] [dy] = [ry]
//     [ G  0   -W^2  ] [dz]   [rz]
// Each second-order cone's W^2 = beta^2 (I + c+ f f^T - c- g g^T) is expanded the sparse
// way by two extra unknowns per cone (p: -1 on the diagonal, couples beta sqrt(c-) g;
// q: +1, couples beta sqrt(c+) f), so the block of z is DIAGONAL: -beta_k^2 on cone k,
// -w_i^2 on the orthant. That block is eliminated in closed form (it is the first block
// any fill-reducing order would pivot on), leaving the reduced quasi-definite matrix
//     [ delta I + G^T D^-1 G    A^T        G^T D^-1 V         G^T D^-1 U      ]
//     [ A                       -delta I   0                  0               ]
//     [ V^T D^-1 G              0          -(q0 - ||q1||)^2   0               ]
//     [ U^T D^-1 G              0          0                  (q0 + ||q1||)^2 ]
// over (x, y, p, q), with O(nnz(A) + nnz(G^T G) + nnz(G)) entries. Since every z pivot of
// cone k is the same -beta_k^2, G_k^T D_k^-1 G_k = G_k^T G_k / beta_k^2 with G_k^T G_k formed
// ONCE: a factorization costs one pass over G (for G^T q-hat) instead of re-summing ~nnz(G)
// rank-one updates. The reduced matrix is ordered once by CAMD (x and y before p and q, so
// the nearly singular direction of W^2 sits in the p pivot, computed exactly as
// -(q0 - ||q1||)^2), its elimination tree comes from SuiteSparse ldl_symbolic, and the
// numeric LDL^T adds ECOS-style dynamic regularization (SuiteSparse's ldl_numeric has
// none). Solutions are polished by iterative refinement on the reduced system without its
// regularization (exact: z is eliminated in closed form), or, when a z pivot itself had
// to be regularized, against the unregularized, unexpanded K.
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "solvers/conic/cones.h"
#include "solvers/conic/constraint_matrix.h"
#include "solvers/conic/ipm_timings.h"
#include "solvers/conic/problem_data.h"

namespace bivo::solvers::conic {

struct KktSettings {
  double static_regularization = 1e-8;  // +delta on x, -delta on y
  int max_refinement_steps = 5;
  double refinement_tolerance = 1e-13;   // stop when ||residual||_inf <= tol (1 + ||rhs||_inf)
  double dynamic_threshold = 1e-13;      // |pivot| below this (or wrong sign) is replaced ...
  double dynamic_regularization = 7e-8;  // ... by sign * this
};

class KktSystem {
 public:
  // clock (may be null): set-up, factorizations, solves and refinement are timed on it.
  KktSystem(const SparseMatrix& A, const ConstraintMatrix& G, const ConeProduct& cones, KktSettings settings,
            IpmClock* clock = nullptr);
  KktSystem() = default;  // set up later
  // (Re)builds the pattern, ordering and symbolic factorization for this A, G and K, in the
  // buffers of the last set-up (kkt_setup.cpp). A, G and cones must outlive the system.
  void setup(const SparseMatrix& A, const ConstraintMatrix& G, const ConeProduct& cones, KktSettings settings,
             IpmClock* clock = nullptr);

  // Numeric factorization for scaling W; false if LDL meets a non-finite pivot.
  bool factor(const NtScaling& w);
  // Solves with the latest factorization; rhs = [rx; ry; rz], returns [dx; dy; dz].
  // Returns false when the refined residual is still not finite. refine = false: one
  // solve with the factors, no residual (for directions that need no full accuracy).
  bool solve(const Eigen::VectorXd& rhs, Eigen::VectorXd& sol, bool refine = true);

  // Refined solves check (and refine) against the unexpanded K too; off, they refine on the
  // reduced system only (no pass over G), which is exact but for rounding in forming it:
  // enough for directions far from the solution, not for the last digits.
  void set_full_refinement(bool on) { full_refinement_ = on; }

  int size() const { return n_ + p_ + m_; }
  int reduced_size() const { return R_; }
  long factor_nonzeros() const { return static_cast<long>(Lp_.empty() ? 0 : Lp_.back()); }
  int last_refinement_steps() const { return last_refine_; }
  int last_dynamic_pivots() const { return dynamic_pivots_; }
  // Floating-point operations since set-up, counted from the patterns (factorizations,
  // triangular solves, products with G, K and A): a measure of the iterations' work that
  // does not depend on the machine's load, against which the polish is budgeted.
  double work() const { return work_; }

 private:
  void residual(const Eigen::VectorXd& rhs, const Eigen::VectorXd& v, Eigen::VectorXd& out);  // rhs - K v
  void reduced_solve(const Eigen::VectorXd& r, Eigen::VectorXd& sol);  // one solve with the factors
  void reduced_rhs(const Eigen::VectorXd& r, Eigen::VectorXd& red);    // z eliminated (a pass over G^T)
  void ldl_solve(Eigen::VectorXd& red);                                // in place, with the factors
  void back_substitute(const Eigen::VectorXd& r, const Eigen::VectorXd& red,
                       Eigen::VectorXd& sol);  // dz (a pass over G)
  void reduced_residual(const Eigen::VectorXd& rhs, const Eigen::VectorXd& v, Eigen::VectorXd& out);
  bool refine_full(const Eigen::VectorXd& rhs, Eigen::VectorXd& sol);
  bool numeric_with_dynamic_regularization();
  double z_pivot(double d);          // d, or dynamic_regularization when d is below the threshold
  int slot(int row, int col) const;  // position of (row, col) in the reduced CSC
  void compress_pattern();           // entries_ to Kp_, Ki_

  const SparseMatrix* A_ = nullptr;
  const ConstraintMatrix* G_ = nullptr;
  const ConeProduct* cones_ = nullptr;
  KktSettings settings_;
  IpmClock* clock_ = nullptr;
  int n_ = 0, p_ = 0, m_ = 0, nsoc_ = 0, R_ = 0;
  NtScaling w_;
  std::vector<int> cone_of_row_;  // -1 on the orthant

  // Reduced matrix, full symmetric CSC; values rebuilt per factorization as
  // base + sum_k soc_val / beta_k^2 + sum_i orth_val / w_i^2 + the p, q couplings.
  std::vector<int> Kp_, Ki_, mirror_;         // mirror_[s]: slot of the transposed entry
  std::vector<std::pair<int, int>> entries_;  // the set-up's (column, row) pairs
  std::vector<double> Kx_, base_;
  std::vector<int> soc_slot_, soc_cone_;  // G_k^T G_k, upper triangle
  std::vector<double> soc_val_;
  std::vector<int> orth_slot_, orth_row_;  // g_i g_i^T per orthant row, upper triangle
  std::vector<double> orth_val_;
  std::vector<int> couple_begin_, couple_col_;  // per cone: columns j with G_k(:, j) != 0
  std::vector<int> couple_p_slot_, couple_q_slot_;
  std::vector<double> head_row_;  // G_k(head, j) for those columns
  std::vector<int> p_diag_, q_diag_;
  // Per-factorization quantities of each cone: inverse pivot, coupling scales, G^T q-hat.
  std::vector<double> inv_d_, inv_b2_, scale_p_, scale_q_;
  Eigen::VectorXd gq_full_;     // dense G: G_k,1^T q-hat over all columns
  Eigen::VectorXd gq_;          // per cone k, the couple columns' (G_k,1^T q-hat) in couple order
  std::vector<int> gq_target_;  // per nonzero of G: its index in gq_, -1 for heads and the orthant
  Eigen::VectorXd qhat_;        // q-hat of every cone, stored at the cone's tail rows (heads unused)

  // Factorization.
  std::vector<int> P_, Pinv_, Lp_, Parent_, Lnz_, Flag_, Pattern_, Li_;
  std::vector<double> Lx_, D_, Y_;
  std::vector<double> sign_;  // expected pivot sign per unpermuted reduced unknown
  // Buffers reused across solves.
  Eigen::VectorXd red_, red_perm_, red_rhs_, red_res_, red_best_, tz_, res_, cand_, new_res_;
  int last_refine_ = 0;
  int dynamic_pivots_ = 0;
  double work_ = 0.0;
  double factor_work_ = 0.0;  // one numeric factorization: 2 sum_j |L(:, j)|^2, set by the set-up
  double g_work_ = 0.0;       // one product with G or G^T
  bool z_regularized_ = false;
  bool full_refinement_ = true;  // a z pivot got the dynamic regularization this factorization
};

}  // namespace bivo::solvers::conic
