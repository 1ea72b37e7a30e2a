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

}  // namespace bivo::solvers::conic
