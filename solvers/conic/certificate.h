#pragma once
// The exit certificate of the conic IPM: the one place that decides which status a point
// supports. Both the iterations (on measures taken from the scaled iterate, residuals.h) and
// the final check of every returned point (measure_point: from the returned x, y, z, s and the
// user's unscaled data, nothing carried over from the iterations) ask `verdict`, so a status
// never rests on a measure that the returned vectors do not reproduce.
//
//   optimal             primal residual, dual residual < feastol; s^T z < abstol or
//                       s^T z / |objective| < reltol; AND the objective gap
//                       |c^T x + b^T y + h^T z| / (1 + |c^T x|) < gaptol; s, z in K;
//   primal infeasible   h^T z + b^T y < 0, ||A^T y + G^T z|| / -(h^T z + b^T y) < feastol, z in K;
//   dual infeasible     c^T x < 0, max(||A x||, ||G x + s||) / -c^T x < feastol, s in K.
// The objective gap is what a point that is feasible only relative to a huge ||h|| cannot fake
// (an active-set guess that leaves a constraint violated by O(1) next to a bound of 1e20).
#include <string>

#include <Eigen/Core>

#include "solvers/conic/ipm_solver.h"
#include "solvers/conic/problem_data.h"

namespace bivo::solvers::conic {

struct Tolerances {
  double feastol = 1e-8, abstol = 1e-8, reltol = 1e-8, gaptol = 1e-8;
};
Tolerances strict_tolerances(const IpmSettings& settings);
Tolerances reduced_tolerances(const IpmSettings& settings);  // the *_inaccurate ones

// What a status is judged on, in the original units. Residual norms are relative as in ECOS:
// primal max(||A x - b|| / max(1, ||b||), ||G x + s - h|| / max(1, ||h||)), dual
// ||A^T y + G^T z + c|| / max(1, ||c||); and the primal residual is also taken block by block,
// max over equality rows of |A_i x - b_i| / (1 + |b_i|) and over cones k (each orthant row
// one) of ||(G x + s - h)_k|| / (1 + ||h_k|| + ||s_k||), since a bound of 1e18 in one row
// would otherwise let ||h|| excuse a violation of O(1) in another.
struct ExitMeasures {
  double primal_objective = 0.0, dual_objective = 0.0;  // c^T x and -(b^T y + h^T z)
  double gap = 0.0, relative_gap = 0.0;                 // s^T z and s^T z / |objective|
  double objective_gap = 0.0;                           // |c^T x + b^T y + h^T z| / (1 + |c^T x|)
  double primal_residual = 0.0, dual_residual = 0.0;
  double cone_violation = 0.0;  // max over s, z of max(0, -min eigenvalue) / (1 + max |entry|)
  // Infeasibility certificates on the unnormalized point:
  double hz_by = 0.0;                 // h^T z + b^T y   (< 0 for a primal infeasibility certificate)
  double primal_infeasibility = 0.0;  // ||A^T y + G^T z|| / -(h^T z + b^T y)
  double cx = 0.0;                    // c^T x           (< 0 for a dual infeasibility certificate)
  double dual_infeasibility = 0.0;    // max(||A x||, ||G x + s||) / -c^T x
};

// The block-by-block part of the primal residual above, from the products as the caller has
// them: row i of G x + s (or A x) is gxs[i] / (scale[i] tau), of s s[i] / (scale[i] tau)
// (scale = nullptr: 1, else constant within each second-order cone, as Equilibration::row_cone;
// s = nullptr for equality rows, each row a block of its own).
double blockwise_residual(const ConeSpec* cones, int rows, const double* gxs, const double* s, const double* h,
                          const double* scale, double tau);

// The status the measures support at the tolerances; kMaxIterations = none.
IpmStatus verdict(const ExitMeasures& m, const Tolerances& t);

// The measures of the point (x, y, z, s) on `problem` as given (unscaled), from scratch.
ExitMeasures measure_point(const ConicProblem& problem, const Eigen::VectorXd& x, const Eigen::VectorXd& y,
                           const Eigen::VectorXd& z, const Eigen::VectorXd& s);

// Sets result's status from its own vectors on `problem` (the data the solver was given,
// unscaled), and its objective, residual and gap fields from the same measures. A claimed
// optimum or certificate that passes at the strict tolerances stands; one that passes only at
// the reduced ones stands with reduced_accuracy and a note saying which strict tolerance fails
// (and whether it lies below the rounding floor given in result.*_floor); one that fails both
// becomes kNumericalTrouble, the note saying what failed. Other exits keep their status.
ExitMeasures certify(const ConicProblem& problem, const IpmSettings& settings, IpmResult& result);  // its measures

// "primal residual 3.1e-07 > 1.0e-08, gap ..." : the strict tolerances the measures miss.
std::string shortfall(const ExitMeasures& m, IpmStatus claim, const Tolerances& t, double primal_floor = 0.0,
                      double dual_floor = 0.0);

}  // namespace bivo::solvers::conic
