#pragma once
// The Newton system of the conic IPM,
//     [ 0  A^T  G^T  ] [dx]   [rx]
//     [ A  0    0    ] [dy] = [ry]
//     [ G  0   -W^2  ] [dz]   [rz]
// with each second-order cone's W^2 = beta^2 (D + u u^T - v v^T) expanded by two extra
// rows/columns per cone (p: -1 on the diagonal, couples beta v; q: +1, couples beta u),
// so the matrix keeps O(nnz(A) + nnz(G) + m) entries and is quasi-definite once the
// static regularization (+delta on x, -delta on y and z) is added. Factored by LDL^T
// in a constrained AMD (CAMD) ordering computed once, elimination tree from SuiteSparse
// ldl_symbolic, numeric LDL with ECOS-style dynamic regularization; solutions are polished by
// iterative refinement against the unregularized, unexpanded matrix.
#include <vector>

#include <Eigen/Core>

#include "solvers/conic/cones.h"
#include "solvers/conic/problem_data.h"

namespace bivo::solvers::conic {

struct KktSettings {
  double static_regularization = 1e-8;  // relative to the largest |entry| of A, G (>= 1)
  int max_refinement_steps = 5;
  double refinement_tolerance = 1e-13;
  double dynamic_threshold = 1e-13;      // |pivot| below this (or wrong sign) is replaced ...
  double dynamic_regularization = 7e-8;  // ... by sign * this  // stop when ||residual||_inf <= tol (1 + ||rhs||_inf)
};

class KktSystem {
 public:
  KktSystem(const SparseMatrix& A, const SparseMatrix& G, const ConeProduct& cones, KktSettings settings);

  // Numeric factorization for scaling W; false if LDL meets a zero pivot.
  bool factor(const NtScaling& w);
  // Solves with the latest factorization; rhs = [rx; ry; rz], returns [dx; dy; dz].
  // Returns false when the refined residual is still not finite.
  bool solve(const Eigen::VectorXd& rhs, Eigen::VectorXd& sol);

  int size() const { return n_ + p_ + m_; }
  int expanded_size() const { return N_; }
  long factor_nonzeros() const { return static_cast<long>(Lp_.empty() ? 0 : Lp_.back()); }
  int last_refinement_steps() const { return last_refine_; }
  int last_dynamic_pivots() const { return dynamic_pivots_; }

 private:
  void multiply_true(const Eigen::VectorXd& v, Eigen::VectorXd& out);  // reduced K v
  void ldl_solve(Eigen::VectorXd& x_expanded);
  bool numeric_with_dynamic_regularization();

  const SparseMatrix& A_;
  const SparseMatrix& G_;
  const ConeProduct& cones_;
  KktSettings settings_;
  int n_, p_, m_, N_;
  double delta_ = 0.0;
  NtScaling w_;

  // Full symmetric CSC of the expanded matrix and the slots updated per factorization.
  std::vector<int> Kp_, Ki_;
  std::vector<double> Kx_;
  std::vector<int> zdiag_, zp_, zq_;      // per z row: diagonal slot, slot of (p_k,z) and (q_k,z)
  std::vector<int> pcol_, qcol_;          // per SOC: first slot of column p_k / q_k (cone rows, then diagonal)

  // Factorization.
  std::vector<int> P_, Pinv_, Lp_, Parent_, Lnz_, Flag_, Pattern_, Li_;
  std::vector<double> Lx_, D_, Y_;
  Eigen::VectorXd work_, work2_;
  // Refinement buffers (reused across solves).
  Eigen::VectorXd residual_, candidate_, new_residual_, kv_, z_, w2z_;
  int last_refine_ = 0;
  int dynamic_pivots_ = 0;
  std::vector<double> sign_;  // expected pivot sign per unpermuted variable
};

}  // namespace bivo::solvers::conic
