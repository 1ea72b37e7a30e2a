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
  SparseMatrix A;  // p x n (p may be 0)
  Eigen::VectorXd b;
  SparseMatrix G;  // m x n, m = cones.dim()
  // Or G as a dense m x n matrix (then G stays 0 x 0): for a G with few columns that are
  // mostly full, as the paper's full form (7 columns, n+1 rows of 6 Jacobian entries), built
  // straight into the layout the solver multiplies with (constraint_matrix.h).
  Eigen::MatrixXd dense_G;
  Eigen::VectorXd h;
  ConeSpec cones;

  int num_variables() const { return static_cast<int>(c.size()); }
  int num_equalities() const { return static_cast<int>(b.size()); }
  int num_cone_rows() const { return static_cast<int>(h.size()); }
  bool has_dense_G() const { return dense_G.size() > 0; }
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

// Ruiz-style infinity-norm equilibration, `passes` sweeps (early stop once every factor is
// within 1 % of 1). The factors are computed without touching the data: a block's largest
// |entry| scales exactly with its row and column factors, so the passes run on the matrix of
// block maxima of [A; G] (one row per equality, per orthant row and per second-order cone),
// formed in one sweep over the data; for the paper's SOCP that is a 2 x 7 matrix.
Equilibration equilibration_factors(const ConicProblem& problem, int passes);
void equilibration_factors(const ConicProblem& problem, int passes, Equilibration& out);  // into out's buffers
// Scales c, b, h and A in place (G is scaled where its copy is made: ConstraintMatrix).
void scale_vectors_and_equalities(ConicProblem& problem, const Equilibration& e);
// Both, and G scaled in place too.
Equilibration equilibrate(ConicProblem& problem, int passes);
Equilibration identity_equilibration(const ConicProblem& problem);

}  // namespace bivo::solvers::conic
