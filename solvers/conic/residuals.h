#pragma once
// Residuals of the homogeneous self-dual embedding and the ECOS-like stopping measures.
//   rx = -(A^T y + G^T z + c tau),  ry = A x - b tau,  rz = s + G x - h tau,
//   rtau = kappa + c^T x + b^T y + h^T z.
// Stopping measures are computed in the ORIGINAL (unequilibrated) units so tolerances
// mean the same with and without equilibration.
#include <Eigen/Core>

#include "solvers/conic/certificate.h"
#include "solvers/conic/constraint_matrix.h"
#include "solvers/conic/problem_data.h"
#include "solvers/conic/variables.h"

namespace bivo::solvers::conic {

struct Residuals : ExitMeasures {
  // Embedding residuals (scaled problem), used by the Newton step.
  Eigen::VectorXd rx, ry, rz;
  double rtau = 0.0;
  // ExitMeasures: of (x, y, z, s)/tau in original units (cone_violation stays 0: iterates
  // are interior by construction); infeasibility measures on the unnormalized iterate.

  // Work space, kept between calls so an iteration allocates nothing.
  Eigen::VectorXd atyz, ax, gx, gxs;
};

// `scaled` is the problem the IPM iterates on (G its constraint matrix), `original` the
// user's, `eq` maps between them.
void compute_residuals(const ConicProblem& scaled, const ConstraintMatrix& G, const ConicProblem& original,
                       const Equilibration& eq, const Variables& v, Residuals& r);

// What double precision can resolve of the two residual measures at v: the rounding of the
// sums that form them, estimated as eps * sqrt(terms) * (sum of |terms|) per entry, in the
// measures' units (original units, same normalization). A tolerance below its floor cannot
// be certified (the paper's full form at n = 3e5: G^T z sums 3e5 terms per column).
struct ResidualFloors {
  double primal = 0.0, dual = 0.0;
};
ResidualFloors residual_floors(const ConicProblem& scaled, const ConstraintMatrix& G, const ConicProblem& original,
                               const Equilibration& eq, const Variables& v);

}  // namespace bivo::solvers::conic
