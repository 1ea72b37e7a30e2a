#pragma once
// The cone-constraint matrix G of the IPM in the layout its products run fastest in.
// Every iteration multiplies by G and G^T a dozen times (KKT solves, refinement, residuals).
// A sparse product gathers through an index per nonzero and, by columns, scatters into the
// result; when G is nearly dense and has few columns (the paper's full form: n+1 rows of
// 6 Jacobian entries, 7 columns) a dense column-major copy turns both into vectorized
// BLAS-2 products at the same memory. Otherwise: G by columns for G^T v (a dot per
// column) and by rows for G x (a dot per row), so neither product scatters.
#include <map>
#include <utility>

#include <Eigen/Core>

#include "solvers/conic/problem_data.h"

namespace bivo::solvers::conic {

using RowMajorMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;

class ConstraintMatrix {
 public:
  // Dense when nnz >= dense_fill * rows * cols and cols <= dense_max_cols.
  explicit ConstraintMatrix(const SparseMatrix& G, double dense_fill = 0.5, int dense_max_cols = 64);

  const SparseMatrix& sparse() const { return G_; }
  const RowMajorMatrix& by_rows() const { return Gr_; }
  bool dense() const { return dense_; }
  int rows() const { return static_cast<int>(G_.rows()); }
  int cols() const { return static_cast<int>(G_.cols()); }

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

 private:
  const SparseMatrix& G_;
  RowMajorMatrix Gr_;
  Eigen::MatrixXd Gd_;
  bool dense_ = false;
  mutable std::map<std::pair<int, int>, SparseMatrix> grams_;
};

}  // namespace bivo::solvers::conic
