#include "solvers/conic/kkt_system.h"

#include <algorithm>
#include <cmath>

extern "C" {
#include <camd.h>
#include <ldl.h>
}

#include "solvers/error.h"

namespace bivo::solvers::conic {

KktSystem::KktSystem(const SparseMatrix& A, const SparseMatrix& G, const ConeProduct& cones,
                     KktSettings settings)
    : A_(A), G_(G), cones_(cones), settings_(settings) {
  n_ = static_cast<int>(std::max(A.cols(), G.cols()));
  p_ = static_cast<int>(A.rows());
  m_ = static_cast<int>(G.rows());
  const int nsoc = cones.soc_count();
  N_ = n_ + p_ + m_ + 2 * nsoc;
  delta_ = settings_.static_regularization;

  const SparseMatrix At = A.transpose();
  const SparseMatrix Gt = G.transpose();
  std::vector<int> cone_of_row(m_, -1);
  for (int k = 0; k < nsoc; ++k) {
    for (int i = 0; i < cones.spec().soc[k]; ++i) cone_of_row[cones.soc_offset(k) + i] = k;
  }
  zdiag_.assign(m_, -1);
  zp_.assign(m_, -1);
  zq_.assign(m_, -1);
  pcol_.assign(nsoc, -1);
  qcol_.assign(nsoc, -1);

  Kp_.assign(N_ + 1, 0);
  Ki_.clear();
  Kx_.clear();
  auto push = [&](int row, double v) {
    Ki_.push_back(row);
    Kx_.push_back(v);
  };
  int col = 0;
  for (int j = 0; j < n_; ++j, ++col) {  // x columns: diagonal, A(:, j), G(:, j)
    Kp_[col] = static_cast<int>(Ki_.size());
    push(j, 0.0);
    if (j < A.cols()) {
      for (SparseMatrix::InnerIterator it(A, j); it; ++it) push(n_ + static_cast<int>(it.row()), it.value());
    }
    if (j < G.cols()) {
      for (SparseMatrix::InnerIterator it(G, j); it; ++it) push(n_ + p_ + static_cast<int>(it.row()), it.value());
    }
  }
  for (int i = 0; i < p_; ++i, ++col) {  // y columns: A(i, :)^T, diagonal
    Kp_[col] = static_cast<int>(Ki_.size());
    for (SparseMatrix::InnerIterator it(At, i); it; ++it) push(static_cast<int>(it.row()), it.value());
    push(n_ + i, 0.0);
  }
  for (int r = 0; r < m_; ++r, ++col) {  // z columns: G(r, :)^T, diagonal, (p_k, q_k)
    Kp_[col] = static_cast<int>(Ki_.size());
    for (SparseMatrix::InnerIterator it(Gt, r); it; ++it) push(static_cast<int>(it.row()), it.value());
    zdiag_[r] = static_cast<int>(Ki_.size());
    push(n_ + p_ + r, 0.0);
    if (cone_of_row[r] >= 0) {
      const int k = cone_of_row[r];
      zp_[r] = static_cast<int>(Ki_.size());
      push(n_ + p_ + m_ + 2 * k, 0.0);
      zq_[r] = static_cast<int>(Ki_.size());
      push(n_ + p_ + m_ + 2 * k + 1, 0.0);
    }
  }
  for (int k = 0; k < nsoc; ++k) {  // p_k then q_k: the cone's z rows, diagonal
    const int o = cones.soc_offset(k), d = cones.spec().soc[k];
    for (int which = 0; which < 2; ++which, ++col) {
      Kp_[col] = static_cast<int>(Ki_.size());
      (which == 0 ? pcol_ : qcol_)[k] = static_cast<int>(Ki_.size());
      for (int i = 0; i < d; ++i) push(n_ + p_ + o + i, 0.0);
      push(col, which == 0 ? -1.0 : 1.0);
    }
  }
  Kp_[N_] = static_cast<int>(Ki_.size());

  // Fill-reducing ordering once (the pattern never changes), constrained to eliminate the
  // z rows first, then x and y, then the expansion columns p, q: z pivots are then exactly
  // -beta^2 or -s/z, and the nearly singular direction of W^2 (eigenvalue beta^2 (q0-||q1||)^2)
  // is formed in the p pivot as -1 + 2 c- instead of as a difference of O(c+) fill terms.
  std::vector<int> constraint(N_, 1);
  for (int r = 0; r < m_; ++r) constraint[n_ + p_ + r] = 0;
  for (int j = n_ + p_ + m_; j < N_; ++j) constraint[j] = 2;
  P_.assign(N_, 0);
  Pinv_.assign(N_, 0);
  double control[CAMD_CONTROL], info[CAMD_INFO];
  camd_defaults(control);
  const int status = camd_order(N_, Kp_.data(), Ki_.data(), P_.data(), control, info, constraint.data());
  if (status != CAMD_OK && status != CAMD_OK_BUT_JUMBLED) {
    throw Error("conic KKT: CAMD ordering failed (status " + std::to_string(status) + ", size " +
                std::to_string(N_) + ")");
  }
  for (int k = 0; k < N_; ++k) Pinv_[P_[k]] = k;
  sign_.assign(N_, -1.0);
  for (int j = 0; j < n_; ++j) sign_[j] = 1.0;
  for (int k = 0; k < nsoc; ++k) sign_[n_ + p_ + m_ + 2 * k + 1] = 1.0;
  Lp_.assign(N_ + 1, 0);
  Parent_.assign(N_, 0);
  Lnz_.assign(N_, 0);
  Flag_.assign(N_, 0);
  Pattern_.assign(N_, 0);
  ldl_symbolic(N_, Kp_.data(), Ki_.data(), Lp_.data(), Parent_.data(), Lnz_.data(), Flag_.data(),
               P_.data(), Pinv_.data());
  Li_.assign(std::max(Lp_[N_], 1), 0);
  Lx_.assign(std::max(Lp_[N_], 1), 0.0);
  D_.assign(N_, 0.0);
  Y_.assign(N_, 0.0);
  work_.resize(N_);
  work2_.resize(N_);
}

bool KktSystem::factor(const NtScaling& w) {
  w_ = w;
  const int l = cones_.spec().nonnegative;
  for (int r = 0; r < l; ++r) Kx_[zdiag_[r]] = -w.orthant_w[r] * w.orthant_w[r];
  for (int k = 0; k < cones_.soc_count(); ++k) {
    const SocScaling& sc = w.soc[k];
    const int o = cones_.soc_offset(k), d = cones_.spec().soc[k];
    const double b2 = sc.beta * sc.beta;
    const double wb1_norm = sc.wb.tail(d - 1).norm();
    const double bp = sc.beta * std::sqrt(sc.cplus), bm = sc.beta * std::sqrt(sc.cminus);
    for (int i = 0; i < d; ++i) {
      const int r = o + i;
      // f = (1, qh), g = (1, -qh), qh = wb1 / ||wb1|| (any unit vector works when q1 = 0).
      const double qh = (i == 0 || wb1_norm == 0.0) ? 0.0 : sc.wb[i] / wb1_norm;
      const double vi = (i == 0 ? bm : -bm * qh);
      const double ui = (i == 0 ? bp : bp * qh);
      Kx_[zdiag_[r]] = -b2;
      Kx_[zp_[r]] = vi;
      Kx_[zq_[r]] = ui;
      Kx_[pcol_[k] + i] = vi;
      Kx_[qcol_[k] + i] = ui;
    }
  }
  for (int j = 0; j < n_; ++j) Kx_[Kp_[j]] = delta_;
  for (int i = 0; i < p_; ++i) Kx_[Kp_[n_ + i + 1] - 1] = -delta_;
  return numeric_with_dynamic_regularization();
}

// Up-looking LDL^T (row k of L from a sparse triangular solve along the elimination tree
// computed by ldl_symbolic), the algorithm of SuiteSparse LDL plus the one thing it lacks:
// dynamic regularization as in ECOS. A quasi-definite matrix has known pivot signs (x and q
// positive; y, z and p negative); a pivot that rounding has driven to zero or to the wrong
// sign (W^{-2} ~ 1e16 swamps delta in the x block near the end) is replaced by
// sign * dynamic_regularization, and iterative refinement against the true matrix repairs
// the perturbation.
bool KktSystem::numeric_with_dynamic_regularization() {
  const int n = N_;
  dynamic_pivots_ = 0;
  for (int k = 0; k < n; ++k) {
    Y_[k] = 0.0;
    int top = n;
    Flag_[k] = k;
    Lnz_[k] = 0;
    const int kk = P_[k];
    for (int q = Kp_[kk]; q < Kp_[kk + 1]; ++q) {
      int i = Pinv_[Ki_[q]];
      if (i > k) continue;  // upper triangle of the permuted matrix only
      Y_[i] += Kx_[q];
      int len = 0;
      for (; Flag_[i] != k; i = Parent_[i]) {
        Pattern_[len++] = i;
        Flag_[i] = k;
      }
      while (len > 0) Pattern_[--top] = Pattern_[--len];
    }
    double dk = Y_[k];
    Y_[k] = 0.0;
    for (; top < n; ++top) {
      const int i = Pattern_[top];
      const double yi = Y_[i];
      Y_[i] = 0.0;
      const int end = Lp_[i] + Lnz_[i];
      for (int q = Lp_[i]; q < end; ++q) Y_[Li_[q]] -= Lx_[q] * yi;
      const double lki = yi / D_[i];
      dk -= lki * yi;
      Li_[end] = k;
      Lx_[end] = lki;
      ++Lnz_[i];
    }
    const double sign = sign_[kk];
    if (!(sign * dk > settings_.dynamic_threshold)) {
      if (!std::isfinite(dk)) return false;
      dk = sign * settings_.dynamic_regularization;
      ++dynamic_pivots_;
    }
    D_[k] = dk;
  }
  return true;
}

void KktSystem::ldl_solve(Eigen::VectorXd& x) {
  ldl_perm(N_, work2_.data(), x.data(), P_.data());
  ldl_lsolve(N_, work2_.data(), Lp_.data(), Li_.data(), Lx_.data());
  ldl_dsolve(N_, work2_.data(), D_.data());
  ldl_ltsolve(N_, work2_.data(), Lp_.data(), Li_.data(), Lx_.data());
  ldl_permt(N_, x.data(), work2_.data(), P_.data());
}

// Reduced K v into out; every buffer is a member sized once, because at the compressed
// problem's 14 cone rows allocation, not arithmetic, dominated a Newton solve.
void KktSystem::multiply_true(const Eigen::VectorXd& v, Eigen::VectorXd& out) {
  const int nr = n_ + p_ + m_;
  out.resize(nr);
  out.head(n_).setZero();
  if (p_ > 0) {
    out.head(n_).noalias() += A_.transpose() * v.segment(n_, p_);
    out.segment(n_, p_).noalias() = A_ * v.head(n_);
  }
  if (m_ > 0) {
    z_ = v.segment(n_ + p_, m_);
    cones_.apply_w_squared(w_, z_, w2z_);
    out.head(n_).noalias() += G_.transpose() * z_;
    out.segment(n_ + p_, m_).noalias() = G_ * v.head(n_);
    out.segment(n_ + p_, m_) -= w2z_;
  }
}

bool KktSystem::solve(const Eigen::VectorXd& rhs, Eigen::VectorXd& sol) {
  const int nr = n_ + p_ + m_;
  sol.setZero(nr);
  residual_ = rhs;
  const double target = settings_.refinement_tolerance * (1.0 + rhs.lpNorm<Eigen::Infinity>());
  double last_norm = std::numeric_limits<double>::infinity();
  last_refine_ = 0;
  for (int step = 0; step <= settings_.max_refinement_steps; ++step) {
    work_.head(nr) = residual_;
    work_.tail(N_ - nr).setZero();
    ldl_solve(work_);
    candidate_ = sol + work_.head(nr);
    multiply_true(candidate_, kv_);
    new_residual_ = rhs - kv_;
    const double norm = new_residual_.lpNorm<Eigen::Infinity>();
    if (!std::isfinite(norm)) return step > 0;
    if (norm >= last_norm) break;  // refinement stalled: keep the better iterate
    sol.swap(candidate_);
    residual_.swap(new_residual_);
    last_norm = norm;
    last_refine_ = step;
    if (norm <= target) break;
  }
  return std::isfinite(last_norm);
}

}  // namespace bivo::solvers::conic
