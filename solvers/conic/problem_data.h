#pragma once
// Problem data of the conic IPM (ECOS standard form):
//   minimize c^T x   subject to   A x = b,   G x + s = h,   s in K
// plus the diagonal equilibration that makes raw-unit data (image gradients ~1e2, depth
// residuals ~1e-2, sums over 3e5 pixels) tractable: x = D xs, rows scaled by E, with one
// common factor per second-order cone so that E keeps K invariant.
#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "solvers/conic/cones.h"

namespace bivo::solvers::conic {

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

struct ConicProblem {
  Eigen::VectorXd c;
  SparseMatrix A;   // p x n (p may be 0)
  Eigen::VectorXd b;
  SparseMatrix G;   // m x n, m = cones.dim()
  Eigen::VectorXd h;
  ConeSpec cones;

  int num_variables() const { return static_cast<int>(c.size()); }
  int num_equalities() const { return static_cast<int>(b.size()); }
  int num_cone_rows() const { return static_cast<int>(h.size()); }
};

// Dimensions agree, cone sizes sum to the rows of G, every entry finite. Throws bivo::Error
// naming the mismatch or the first non-finite entry.
void validate(const ConicProblem& problem);

// Scaled problem: As = Ea A D, Gs = Eg G D, cs = D c, bs = Ea b, hs = Eg h.
// Original solution: x = D xs, y = Ea ys, z = Eg zs, s = Eg^{-1} ss.
struct Equilibration {
  Eigen::VectorXd col;       // D
  Eigen::VectorXd row_eq;    // Ea
  Eigen::VectorXd row_cone;  // Eg (constant within each second-order cone)
};

// Ruiz-style infinity-norm equilibration, `passes` rounds, applied in place.
Equilibration equilibrate(ConicProblem& problem, int passes);
Equilibration identity_equilibration(const ConicProblem& problem);

}  // namespace bivo::solvers::conic
