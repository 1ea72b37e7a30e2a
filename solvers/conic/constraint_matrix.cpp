#include "solvers/conic/constraint_matrix.h"

#include <algorithm>

#include "solvers/conic/dense_kernels.h"

namespace bivo::solvers::conic {

namespace {

// One timed, counted pass over G.
struct GPass {
  explicit GPass(IpmClock* clock) : scope(clock, IpmPhase::kGPasses) {
    if (scope.active()) ++clock->timings().g_passes;
  }
  PhaseScope scope;
};

// Dense products by blocks of rows: a block of every column stays in L1, so G x writes its
// result once (not once per column, as a column-major GEMV does) and G^T v reads v once.
constexpr Eigen::Index kBlock = 512;

using Ranges = std::vector<Eigen::Index>;

// out(0 .. count) (= or +=) a G(begin .. begin + count, :) x; column j only over its
// nonzero rows [first[j], last[j]).
void dense_gx(const Eigen::MatrixXd& G, const Ranges& first, const Ranges& last, Eigen::Index begin, Eigen::Index count,
              const double* x, double a, bool accumulate, double* out) {
  const Eigen::Index cols = G.cols();
  for (Eigen::Index i0 = 0; i0 < count; i0 += kBlock) {
    const Eigen::Index len = std::min(kBlock, count - i0), r0 = begin + i0, r1 = r0 + len;
    double* o = out + i0;
    bool written = accumulate;
    for (Eigen::Index j = 0; j < cols; ++j) {
      const Eigen::Index lo = std::max(r0, first[j]), hi = std::min(r1, last[j]);
      if (lo >= hi) continue;
      if (!written) {
        written = true;
        if (lo == r0 && hi == r1) {
          kernels::scaled_copy(len, a * x[j], G.col(j).data() + r0, o);
          continue;
        }
        std::fill(o, o + len, 0.0);
      }
      kernels::axpy(hi - lo, a * x[j], G.col(j).data() + lo, o + (lo - r0));
    }
    if (!written) std::fill(o, o + len, 0.0);
  }
}

// out += a G(begin .. begin + count, :)^T v, each column over its nonzero rows.
void dense_gtv(const Eigen::MatrixXd& G, const Ranges& first, const Ranges& last, Eigen::Index begin,
               Eigen::Index count, const double* v, double a, double* out) {
  const Eigen::Index cols = G.cols();
  for (Eigen::Index j = 0; j < cols; ++j) {
    const Eigen::Index lo = std::max(begin, first[j]), hi = std::min(begin + count, last[j]);
    if (lo < hi) out[j] += a * kernels::dot(hi - lo, G.col(j).data() + lo, v + (lo - begin));
  }
}

}  // namespace

ConstraintMatrix::ConstraintMatrix(const SparseMatrix& G, double dense_fill, int dense_max_cols) {
  build(G, nullptr, nullptr, dense_fill, dense_max_cols);
}

ConstraintMatrix::ConstraintMatrix(const SparseMatrix& G, const Eigen::VectorXd& row_scale,
                                   const Eigen::VectorXd& col_scale, double dense_fill, int dense_max_cols) {
  build(G, &row_scale, &col_scale, dense_fill, dense_max_cols);
}

void ConstraintMatrix::assign(const SparseMatrix& G, const Eigen::VectorXd& row_scale, const Eigen::VectorXd& col_scale,
                              double dense_fill, int dense_max_cols) {
  grams_.clear();
  dense_grams_.clear();
  build(G, &row_scale, &col_scale, dense_fill, dense_max_cols);
}

void ConstraintMatrix::assign(const Eigen::MatrixXd& G, const Eigen::VectorXd& row_scale,
                              const Eigen::VectorXd& col_scale) {
  grams_.clear();
  dense_grams_.clear();
  rows_ = static_cast<int>(G.rows());
  cols_ = static_cast<int>(G.cols());
  dense_ = rows_ > 0 && cols_ > 0;
  if (!dense_) {
    G_.resize(rows_, cols_);
    Gr_ = G_;
    return;
  }
  Gd_.resize(rows_, cols_);
  for (int j = 0; j < cols_; ++j) Gd_.col(j) = G.col(j).cwiseProduct(row_scale) * col_scale[j];
  find_column_ranges();
}

void ConstraintMatrix::find_column_ranges() {
  first_.assign(cols_, 0);
  last_.assign(cols_, 0);
  for (int j = 0; j < cols_; ++j) {
    const double* col = Gd_.col(j).data();
    Eigen::Index lo = 0, hi = rows_;
    while (lo < hi && col[lo] == 0.0) ++lo;
    while (hi > lo && col[hi - 1] == 0.0) --hi;
    first_[j] = lo;
    last_[j] = hi;
  }
}

void ConstraintMatrix::build(const SparseMatrix& G, const Eigen::VectorXd* row_scale, const Eigen::VectorXd* col_scale,
                             double dense_fill, int dense_max_cols) {
  rows_ = static_cast<int>(G.rows());
  cols_ = static_cast<int>(G.cols());
  const double cells = static_cast<double>(G.rows()) * static_cast<double>(G.cols());
  dense_ = G.cols() > 0 && G.rows() > 0 && G.cols() <= dense_max_cols &&
           static_cast<double>(G.nonZeros()) >= dense_fill * cells;
  auto value = [&](int i, int j, double v) { return row_scale ? v * (*row_scale)[i] * (*col_scale)[j] : v; };
  if (dense_) {
    Gd_.setZero(rows_, cols_);
    const int* inner = G.innerIndexPtr();
    const double* val = G.valuePtr();
    for (int j = 0; j < cols_; ++j) {
      double* col = Gd_.col(j).data();
      const int begin = G.outerIndexPtr()[j];
      const int end = G.isCompressed() ? G.outerIndexPtr()[j + 1] : begin + G.innerNonZeroPtr()[j];
      if (row_scale) {
        const double* rs = row_scale->data();
        const double cs = (*col_scale)[j];
        for (int e = begin; e < end; ++e) col[inner[e]] += val[e] * rs[inner[e]] * cs;
      } else {
        for (int e = begin; e < end; ++e) col[inner[e]] += val[e];
      }
    }
    find_column_ranges();
  } else {
    G_ = G;
    G_.makeCompressed();
    if (row_scale) {
      for (int j = 0; j < G_.outerSize(); ++j) {
        for (SparseMatrix::InnerIterator it(G_, j); it; ++it)
          it.valueRef() = value(static_cast<int>(it.row()), j, it.value());
      }
    }
    Gr_ = G_;
  }
}

void ConstraintMatrix::multiply(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> out) const {
  const GPass pass(clock_);
  if (dense_) {
    dense_gx(Gd_, first_, last_, 0, rows_, x.data(), 1.0, false, out.data());
  } else {
    out.noalias() = Gr_ * x;
  }
}

void ConstraintMatrix::add_multiply(double a, const Eigen::Ref<const Eigen::VectorXd>& x,
                                    Eigen::Ref<Eigen::VectorXd> out) const {
  const GPass pass(clock_);
  if (dense_) {
    dense_gx(Gd_, first_, last_, 0, rows_, x.data(), a, true, out.data());
  } else {
    out.noalias() += a * (Gr_ * x);
  }
}

void ConstraintMatrix::multiply_transpose(const Eigen::Ref<const Eigen::VectorXd>& v,
                                          Eigen::Ref<Eigen::VectorXd> out) const {
  const GPass pass(clock_);
  if (dense_) {
    out.setZero();
    dense_gtv(Gd_, first_, last_, 0, rows_, v.data(), 1.0, out.data());
  } else {
    out.noalias() = G_.transpose() * v;
  }
}

void ConstraintMatrix::add_multiply_transpose(double a, const Eigen::Ref<const Eigen::VectorXd>& v,
                                              Eigen::Ref<Eigen::VectorXd> out) const {
  const GPass pass(clock_);
  if (dense_) {
    dense_gtv(Gd_, first_, last_, 0, rows_, v.data(), a, out.data());
  } else {
    out.noalias() += a * (G_.transpose() * v);
  }
}

void ConstraintMatrix::add_rows_multiply_transpose(int begin, int count, double a,
                                                   const Eigen::Ref<const Eigen::VectorXd>& v,
                                                   Eigen::Ref<Eigen::VectorXd> out) const {
  const GPass pass(clock_);
  if (dense_) {
    dense_gtv(Gd_, first_, last_, begin, count, v.data(), a, out.data());
  } else {
    out.noalias() += a * (Gr_.middleRows(begin, count).transpose() * v);
  }
}

Eigen::MatrixXd ConstraintMatrix::dense_rows(int begin, int count) const {
  if (dense_) return Gd_.middleRows(begin, count);
  return Eigen::MatrixXd(Gr_.middleRows(begin, count));
}

RowMajorMatrix ConstraintMatrix::sparse_rows(int begin, int count) const {
  if (dense_) return RowMajorMatrix(Gd_.middleRows(begin, count).sparseView());
  return Gr_.middleRows(begin, count);
}

const Eigen::MatrixXd& ConstraintMatrix::dense_gram(int begin, int count) const {
  Eigen::MatrixXd& g = dense_grams_[{begin, count}];
  if (g.size() > 0 || cols() == 0) return g;
  g.setZero(cols(), cols());
  if (dense_) {
    for (int j = 0; j < cols(); ++j) {
      for (int k = 0; k <= j; ++k) {
        const Eigen::Index lo = std::max<Eigen::Index>({begin, first_[j], first_[k]});
        const Eigen::Index hi = std::min<Eigen::Index>({begin + count, last_[j], last_[k]});
        g(j, k) = g(k, j) = lo < hi ? kernels::dot(hi - lo, Gd_.col(j).data() + lo, Gd_.col(k).data() + lo) : 0.0;
      }
    }
  } else {
    g = Eigen::MatrixXd(gram(begin, count));
  }
  return g;
}

const SparseMatrix& ConstraintMatrix::gram(int begin, int count) const {
  SparseMatrix& g = grams_[{begin, count}];
  if (g.size() > 0 || cols() == 0) return g;
  if (dense_) {
    g = dense_gram(begin, count).sparseView();
  } else {
    const SparseMatrix block = Gr_.middleRows(begin, count);
    g = SparseMatrix(block.transpose()) * block;
  }
  return g;
}

}  // namespace bivo::solvers::conic
