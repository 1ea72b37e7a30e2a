#pragma once
// The cone-constraint matrix G of the IPM in the layout its products run fastest in.
// Every iteration multiplies by G and G^T a dozen times (KKT solves, refinement, residuals).
// A sparse product gathers through an index per nonzero and, by columns, scatters into the
// result; when G is nearly dense and has few columns (the paper's full form: n+1 rows of
// 6 Jacobian entries, 7 columns) a dense column-major copy turns both into vectorized
// BLAS-2 products at the same memory. Otherwise: G by columns for G^T v (a dot per
// column) and by rows for G x (a dot per row), so neither product scatters.
// The matrix is a copy, optionally equilibrated on the way in (E G D in one sweep).
#include <map>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "solvers/conic/ipm_timings.h"
#include "solvers/conic/problem_data.h"

namespace bivo::solvers::conic {

using RowMajorMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;

class ConstraintMatrix {
 public:
  ConstraintMatrix() = default;
  // Dense when nnz >= dense_fill * rows * cols and cols <= dense_max_cols.
  explicit ConstraintMatrix(const SparseMatrix& G, double dense_fill = 0.5, int dense_max_cols = 64);
  // The copy is diag(row_scale) G diag(col_scale).
  ConstraintMatrix(const SparseMatrix& G, const Eigen::VectorXd& row_scale, const Eigen::VectorXd& col_scale,
                   double dense_fill = 0.5, int dense_max_cols = 64);

  // Replaces the matrix by diag(row_scale) G diag(col_scale), in the buffers of the last one
  // (a solver workspace: no fresh memory when the size is the same); cached Gram matrices
  // are dropped.
  void assign(const SparseMatrix& G, const Eigen::VectorXd& row_scale, const Eigen::VectorXd& col_scale,
              double dense_fill = 0.5, int dense_max_cols = 64);
  // A dense G, kept dense: one scaled copy, no scatter.
  void assign(const Eigen::MatrixXd& G, const Eigen::VectorXd& row_scale, const Eigen::VectorXd& col_scale);

  // By columns, compressed; only when !dense() (a dense G keeps no sparse copy).
  const SparseMatrix& sparse() const { return G_; }
  const RowMajorMatrix& by_rows() const { return Gr_; }
  const Eigen::MatrixXd& dense_matrix() const { return Gd_; }
  bool dense() const { return dense_; }
  int rows() const { return rows_; }
  int cols() const { return cols_; }
  double coeff(int row, int col) const { return dense_ ? Gd_(row, col) : G_.coeff(row, col); }

  // out = G x (assigned), out -= G x, out = G^T v, out += / -= G^T v.
  void multiply(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> out) const;
  void multiply_transpose(const Eigen::Ref<const Eigen::VectorXd>& v, Eigen::Ref<Eigen::VectorXd> out) const;
  void add_multiply_transpose(double a, const Eigen::Ref<const Eigen::VectorXd>& v,
                              Eigen::Ref<Eigen::VectorXd> out) const;  // out += a G^T v
  void add_multiply(double a, const Eigen::Ref<const Eigen::VectorXd>& x,
                    Eigen::Ref<Eigen::VectorXd> out) const;  // out += a G x
  // Row blocks (one cone): out += a G(rows)^T v, v of length `count`; and the block as a
  // dense count x cols matrix (for small active sets and cone Gram matrices).
  void add_rows_multiply_transpose(int begin, int count, double a, const Eigen::Ref<const Eigen::VectorXd>& v,
                                   Eigen::Ref<Eigen::VectorXd> out) const;
  Eigen::MatrixXd dense_rows(int begin, int count) const;
  RowMajorMatrix sparse_rows(int begin, int count) const;
  // G(rows)^T G(rows) of a row block (exact zeros dropped), by a dense product when G is dense;
  // formed on first request and kept (the KKT system and the polisher share a cone's).
  const SparseMatrix& gram(int begin, int count) const;
  const Eigen::MatrixXd& dense_gram(int begin, int count) const;
  // Products are timed (and counted) as IpmPhase::kGPasses on this clock; null = untimed.
  void set_clock(IpmClock* clock) const { clock_ = clock; }

 private:
  void build(const SparseMatrix& G, const Eigen::VectorXd* row_scale, const Eigen::VectorXd* col_scale,
             double dense_fill, int dense_max_cols);

  void find_column_ranges();

  mutable IpmClock* clock_ = nullptr;
  // Dense layout: per column the rows [first, last) outside which it is zero (the paper's
  // column of t has one entry), so products skip the zeros.
  std::vector<Eigen::Index> first_, last_;
  SparseMatrix G_;
  RowMajorMatrix Gr_;
  Eigen::MatrixXd Gd_;
  bool dense_ = false;
  int rows_ = 0, cols_ = 0;
  mutable std::map<std::pair<int, int>, SparseMatrix> grams_;
  mutable std::map<std::pair<int, int>, Eigen::MatrixXd> dense_grams_;
};

}  // namespace bivo::solvers::conic
