#include "solvers/conic/constraint_matrix.h"

namespace bivo::solvers::conic {

ConstraintMatrix::ConstraintMatrix(const SparseMatrix& G, double dense_fill, int dense_max_cols) : G_(G) {
  const double cells = static_cast<double>(G.rows()) * static_cast<double>(G.cols());
  dense_ = G.cols() > 0 && G.rows() > 0 && G.cols() <= dense_max_cols &&
           static_cast<double>(G.nonZeros()) >= dense_fill * cells;
  if (dense_) {
    Gd_ = Eigen::MatrixXd(G);
  } else {
    Gr_ = G;
  }
}

void ConstraintMatrix::multiply(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> out) const {
  if (dense_) {
    out.noalias() = Gd_ * x;
  } else {
    out.noalias() = Gr_ * x;
  }
}

void ConstraintMatrix::add_multiply(double a, const Eigen::Ref<const Eigen::VectorXd>& x,
                                    Eigen::Ref<Eigen::VectorXd> out) const {
  if (dense_) {
    out.noalias() += a * (Gd_ * x);
  } else {
    out.noalias() += a * (Gr_ * x);
  }
}

void ConstraintMatrix::multiply_transpose(const Eigen::Ref<const Eigen::VectorXd>& v,
                                          Eigen::Ref<Eigen::VectorXd> out) const {
  if (dense_) {
    out.noalias() = Gd_.transpose() * v;
  } else {
    out.noalias() = G_.transpose() * v;
  }
}

void ConstraintMatrix::add_multiply_transpose(double a, const Eigen::Ref<const Eigen::VectorXd>& v,
                                              Eigen::Ref<Eigen::VectorXd> out) const {
  if (dense_) {
    out.noalias() += a * (Gd_.transpose() * v);
  } else {
    out.noalias() += a * (G_.transpose() * v);
  }
}

void ConstraintMatrix::add_rows_multiply_transpose(int begin, int count, double a,
                                                   const Eigen::Ref<const Eigen::VectorXd>& v,
                                                   Eigen::Ref<Eigen::VectorXd> out) const {
  if (dense_) {
    out.noalias() += a * (Gd_.middleRows(begin, count).transpose() * v);
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

const SparseMatrix& ConstraintMatrix::gram(int begin, int count) const {
  SparseMatrix& g = grams_[{begin, count}];
  if (g.size() > 0 || cols() == 0) return g;
  if (dense_) {
    const Eigen::MatrixXd d = Gd_.middleRows(begin, count).transpose() * Gd_.middleRows(begin, count);
    g = d.sparseView();
  } else {
    const SparseMatrix block = Gr_.middleRows(begin, count);
    g = SparseMatrix(block.transpose()) * block;
  }
  return g;
}

}  // namespace bivo::solvers::conic
