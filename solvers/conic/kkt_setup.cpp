// KktSystem's set-up (kkt_system.h): the pattern of the reduced matrix, the constant parts of
// its values, the fill-reducing ordering and the symbolic factorization, once per solve, in
// the buffers of the last set-up.
#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

extern "C" {
#include <camd.h>
#include <ldl.h>
}

#include "solvers/conic/kkt_system.h"
#include "solvers/error.h"

namespace bivo::solvers::conic {

void KktSystem::setup(const SparseMatrix& A, const ConstraintMatrix& Gm, const ConeProduct& cones, KktSettings settings,
                      IpmClock* clock) {
  A_ = &A;
  G_ = &Gm;
  cones_ = &cones;
  settings_ = settings;
  clock_ = clock;
  last_refine_ = dynamic_pivots_ = 0;
  z_regularized_ = false;
  full_refinement_ = true;
  for (std::vector<int>* v : {&soc_slot_, &soc_cone_, &orth_slot_, &orth_row_, &couple_col_, &couple_p_slot_,
                              &couple_q_slot_, &p_diag_, &q_diag_}) {
    v->clear();
  }
  soc_val_.clear();
  orth_val_.clear();
  head_row_.clear();
  PhaseScope setup_phase(clock_, IpmPhase::kKktSetup);
  if (clock_) ++clock_->timings().kkt_setups;
  const SparseMatrix& G = Gm.sparse();  // empty when Gm is dense
  if (!A.isCompressed()) throw Error("conic KKT: A must be compressed");
  n_ = std::max(static_cast<int>(A.cols()), Gm.cols());
  p_ = static_cast<int>(A.rows());
  m_ = Gm.rows();
  nsoc_ = cones.soc_count();
  R_ = n_ + p_ + 2 * nsoc_;
  const int l = cones.spec().nonnegative;
  cone_of_row_.assign(m_, -1);
  for (int k = 0; k < nsoc_; ++k) {
    for (int i = 0; i < cones.spec().soc[k]; ++i) cone_of_row_[cones.soc_offset(k) + i] = k;
  }
  const int pk0 = n_ + p_;  // p_k = pk0 + 2k, q_k = pk0 + 2k + 1
  // G_k^T G_k per cone (constant: the z pivots of cone k are all -beta_k^2), the orthant
  // rows' outer products, and the columns each cone couples to (nonzero columns of G_k).
  const RowMajorMatrix Gl = Gm.sparse_rows(0, l);
  std::vector<SparseMatrix> gram(nsoc_);
  std::vector<std::vector<int>> couple(nsoc_);
  for (int k = 0; k < nsoc_; ++k) {
    gram[k] = Gm.gram(cones.soc_offset(k), cones.spec().soc[k]);
    for (int j = 0; j < n_; ++j) {
      if (gram[k].coeff(j, j) > 0.0) couple[k].push_back(j);
    }
  }
  std::vector<std::pair<int, int>>& entries = entries_;  // (col, row), both triangles, with repeats
  entries.clear();
  auto add = [&](int r, int c) {
    entries.emplace_back(c, r);
    if (r != c) entries.emplace_back(r, c);
  };
  for (int j = 0; j < R_; ++j) add(j, j);
  for (int j = 0; j < A.outerSize(); ++j) {
    for (SparseMatrix::InnerIterator it(A, j); it; ++it) add(j, n_ + static_cast<int>(it.row()));
  }
  for (int k = 0; k < nsoc_; ++k) {
    for (int j = 0; j < gram[k].outerSize(); ++j) {
      for (SparseMatrix::InnerIterator it(gram[k], j); it; ++it) {
        if (it.row() <= j) add(static_cast<int>(it.row()), j);
      }
    }
    for (int j : couple[k]) {
      add(j, pk0 + 2 * k);
      add(j, pk0 + 2 * k + 1);
    }
  }
  for (int r = 0; r < l; ++r) {
    for (RowMajorMatrix::InnerIterator a(Gl, r); a; ++a) {
      for (RowMajorMatrix::InnerIterator b(Gl, r); b; ++b) {
        if (a.col() <= b.col()) add(static_cast<int>(a.col()), static_cast<int>(b.col()));
      }
    }
  }
  compress_pattern();
  Kx_.assign(Ki_.size(), 0.0);
  // The pattern is symmetric with sorted columns: walking the columns in order, entry (i, j)
  // is the next unvisited one of column i (a transpose without searches).
  mirror_.resize(Ki_.size());
  Flag_.assign(Kp_.begin(), Kp_.end() - 1);
  for (int j = 0; j < R_; ++j) {
    for (int s = Kp_[j]; s < Kp_[j + 1]; ++s) mirror_[s] = Flag_[Ki_[s]]++;
  }
  // Constant values: +-delta and A; then the lists updated per factorization.
  base_.assign(Ki_.size(), 0.0);
  const double delta = settings_.static_regularization;
  for (int j = 0; j < n_; ++j) base_[slot(j, j)] = delta;
  for (int i = 0; i < p_; ++i) base_[slot(n_ + i, n_ + i)] = -delta;
  for (int j = 0; j < A.outerSize(); ++j) {
    for (SparseMatrix::InnerIterator it(A, j); it; ++it) base_[slot(j, n_ + static_cast<int>(it.row()))] += it.value();
  }
  for (int k = 0; k < nsoc_; ++k) {
    for (int j = 0; j < gram[k].outerSize(); ++j) {
      for (SparseMatrix::InnerIterator it(gram[k], j); it; ++it) {
        if (it.row() > j) continue;
        soc_slot_.push_back(slot(static_cast<int>(it.row()), j));
        soc_cone_.push_back(k);
        soc_val_.push_back(it.value());
      }
    }
  }
  for (int r = 0; r < l; ++r) {
    for (RowMajorMatrix::InnerIterator a(Gl, r); a; ++a) {
      for (RowMajorMatrix::InnerIterator b(Gl, r); b; ++b) {
        if (a.col() > b.col()) continue;
        orth_slot_.push_back(slot(static_cast<int>(a.col()), static_cast<int>(b.col())));
        orth_row_.push_back(r);
        orth_val_.push_back(a.value() * b.value());
      }
    }
  }
  couple_begin_.assign(nsoc_ + 1, 0);
  for (int k = 0; k < nsoc_; ++k) {
    const int o = cones.soc_offset(k);
    for (int j : couple[k]) {
      couple_col_.push_back(j);
      couple_p_slot_.push_back(slot(j, pk0 + 2 * k));
      couple_q_slot_.push_back(slot(j, pk0 + 2 * k + 1));
      head_row_.push_back(Gm.coeff(o, j));
    }
    couple_begin_[k + 1] = static_cast<int>(couple_col_.size());
    p_diag_.push_back(slot(pk0 + 2 * k, pk0 + 2 * k));
    q_diag_.push_back(slot(pk0 + 2 * k + 1, pk0 + 2 * k + 1));
  }
  gq_.resize(static_cast<Eigen::Index>(couple_col_.size()));
  // Each nonzero of G below a cone's head adds to that cone's G^T q-hat at its column
  // (G is compressed: the IPM compresses its copy; couple columns are sorted per cone).
  // A dense G takes dense row-block products instead.
  gq_target_.assign(Gm.dense() ? 0 : G.nonZeros(), -1);
  for (int j = 0; j < (Gm.dense() ? 0 : G.outerSize()); ++j) {
    for (int e = G.outerIndexPtr()[j]; e < G.outerIndexPtr()[j + 1]; ++e) {
      const int r = G.innerIndexPtr()[e], k = cone_of_row_[r];
      if (k < 0 || r == cones.soc_offset(k)) continue;
      const auto first = couple_col_.begin() + couple_begin_[k], last = couple_col_.begin() + couple_begin_[k + 1];
      const auto it = std::lower_bound(first, last, j);
      if (it != last && *it == j) gq_target_[e] = static_cast<int>(it - couple_col_.begin());
    }
  }
  qhat_ = Eigen::VectorXd::Zero(m_);
  inv_d_.assign(m_, 1.0);
  scale_p_.assign(nsoc_, 0.0);
  scale_q_.assign(nsoc_, 0.0);
  // Fill-reducing ordering once (the pattern never changes), x and y before p and q.
  PhaseScope ordering_phase(clock_, IpmPhase::kOrdering);
  std::vector<int> constraint(R_, 0);
  for (int j = pk0; j < R_; ++j) constraint[j] = 1;
  P_.assign(R_, 0);
  Pinv_.assign(R_, 0);
  double control[CAMD_CONTROL], info[CAMD_INFO];
  camd_defaults(control);
  const int status = camd_order(R_, Kp_.data(), Ki_.data(), P_.data(), control, info, constraint.data());
  if (status != CAMD_OK && status != CAMD_OK_BUT_JUMBLED) {
    throw Error("conic KKT: CAMD ordering failed (status " + std::to_string(status) + ", size " + std::to_string(R_) +
                ")");
  }
  for (int k = 0; k < R_; ++k) Pinv_[P_[k]] = k;
  sign_.assign(R_, -1.0);
  for (int j = 0; j < n_; ++j) sign_[j] = 1.0;
  for (int k = 0; k < nsoc_; ++k) sign_[pk0 + 2 * k + 1] = 1.0;
  PhaseScope symbolic_phase(clock_, IpmPhase::kSymbolic);
  Lp_.assign(R_ + 1, 0);
  Parent_.assign(R_, 0);
  Lnz_.assign(R_, 0);
  Flag_.assign(R_, 0);
  Pattern_.assign(R_, 0);
  ldl_symbolic(R_, Kp_.data(), Ki_.data(), Lp_.data(), Parent_.data(), Lnz_.data(), Flag_.data(), P_.data(),
               Pinv_.data());
  factor_work_ = 0.0;
  for (int j = 0; j < R_; ++j) factor_work_ += 2.0 * static_cast<double>(Lnz_[j]) * Lnz_[j] + 2.0;
  g_work_ = 2.0 * (Gm.dense() ? static_cast<double>(m_) * n_ : static_cast<double>(G.nonZeros()));
  // The set-up itself: the pattern (a sort of its entries) and the ordering.
  work_ = 8.0 * static_cast<double>(Ki_.size()) * std::log2(2.0 + static_cast<double>(Ki_.size())) + g_work_;
  Li_.assign(std::max(Lp_[R_], 1), 0);
  Lx_.assign(std::max(Lp_[R_], 1), 0.0);
  D_.assign(R_, 0.0);
  Y_.assign(R_, 0.0);
  red_.resize(R_);
  red_perm_.resize(R_);
}

// entries_ to the CSC pattern (Kp_, Ki_), rows sorted and unique per column: a bucket pass
// by column, repeats dropped with a marker, then a sort of each (short) column; a sort of
// all the pairs was a sixth of a small problem's solve.
void KktSystem::compress_pattern() {
  Kp_.assign(R_ + 1, 0);
  for (const auto& e : entries_) ++Kp_[e.first + 1];
  for (int j = 0; j < R_; ++j) Kp_[j + 1] += Kp_[j];
  Flag_.assign(R_, 0);  // next free position per column (Flag_ is the symbolic step's scratch)
  for (int j = 0; j < R_; ++j) Flag_[j] = Kp_[j];
  Pattern_.resize(entries_.size());
  for (const auto& e : entries_) Pattern_[Flag_[e.first]++] = e.second;
  Lnz_.assign(R_, -1);  // marker: the last column each row was seen in
  Ki_.clear();
  int begin = 0;
  for (int j = 0; j < R_; ++j) {
    const int first = static_cast<int>(Ki_.size());
    for (int q = begin; q < Kp_[j + 1]; ++q) {
      const int r = Pattern_[q];
      if (Lnz_[r] == j) continue;
      Lnz_[r] = j;
      Ki_.push_back(r);
    }
    std::sort(Ki_.begin() + first, Ki_.end());
    begin = Kp_[j + 1];
    Kp_[j] = first;
  }
  Kp_[R_] = static_cast<int>(Ki_.size());
}

int KktSystem::slot(int row, int col) const {
  const auto first = Ki_.begin() + Kp_[col], last = Ki_.begin() + Kp_[col + 1];
  const auto it = std::lower_bound(first, last, row);
  if (it == last || *it != row) throw Error("conic KKT: internal pattern error");
  return static_cast<int>(it - Ki_.begin());
}

}  // namespace bivo::solvers::conic
