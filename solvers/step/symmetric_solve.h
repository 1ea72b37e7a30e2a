#pragma once
// Solving A x = -g for a symmetric positive semidefinite A (6x6 in odometry): LDL^T when A is
// safely nonsingular, otherwise the minimum-norm least-squares solution through the
// eigendecomposition (eigenvalues <= rank_tolerance * largest treated as zero).
#include <Eigen/Core>

namespace bivo::solvers {

struct SymmetricSolve {
  Eigen::VectorXd x;
  bool rank_deficient = false;
  int rank = 0;
};

SymmetricSolve solve_symmetric_psd(const Eigen::MatrixXd& A, const Eigen::VectorXd& rhs, double rank_tolerance = 1e-13);

}  // namespace bivo::solvers
