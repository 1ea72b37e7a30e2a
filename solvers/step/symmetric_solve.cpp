#include "solvers/step/symmetric_solve.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

namespace bivo::solvers {

SymmetricSolve solve_symmetric_psd(const Eigen::MatrixXd& A, const Eigen::VectorXd& rhs, double rank_tolerance) {
  SymmetricSolve out;
  const Eigen::Index n = A.rows();
  // LDL^T is the fast path; its pivots bound the conditioning well enough to decide when the
  // minimum-norm fallback is needed (rcond is the LDL^T-based reciprocal condition estimate).
  Eigen::LDLT<Eigen::MatrixXd> ldlt(A);
  if (ldlt.info() == Eigen::Success && ldlt.isPositive() && ldlt.rcond() > rank_tolerance * 10.0 &&
      ldlt.vectorD().minCoeff() > 1e3 * rank_tolerance * ldlt.vectorD().cwiseAbs().maxCoeff()) {
    out.x = ldlt.solve(rhs);
    out.rank = static_cast<int>(n);
    if (out.x.allFinite()) return out;
  }
  // Minimum-norm solution: x = V diag(1/s_i for s_i > tol s_max) V^T rhs.
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(A);
  const Eigen::VectorXd& s = eig.eigenvalues();
  const double smax = s.cwiseAbs().maxCoeff();
  const double cut = rank_tolerance * smax;
  Eigen::VectorXd coeff = eig.eigenvectors().transpose() * rhs;
  int rank = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (s(i) > cut && s(i) > 0.0) {
      coeff(i) /= s(i);
      ++rank;
    } else {
      coeff(i) = 0.0;
    }
  }
  out.x = eig.eigenvectors() * coeff;
  out.rank = rank;
  out.rank_deficient = rank < n;
  return out;
}

}  // namespace bivo::solvers
