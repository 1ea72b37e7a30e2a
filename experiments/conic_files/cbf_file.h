#pragma once
// Conic programs in the Conic Benchmark Format (CBF, the text format of the CBLIB library,
// versions 1-4) for `bivo conic FILE.cbf`. A CBF file states
//   min/max  c^T x + c0   s.t.   x in K_var,   A x + b in K_con
// with K_var, K_con products of the cones
//   F (free), L+ (>= 0), L- (<= 0), L= (= 0), Q (x0 >= ||x1:||), QR (2 x0 x1 >= ||x2:||^2, x0, x1 >= 0)
// over consecutive rows (keywords VER, OBJSENSE, VAR, CON, OBJACOORD, OBJBCOORD, ACOORD,
// BCOORD). It becomes the IPM's form (min c^T x, A x = b, G x + s = h, s in R+ x Q..):
// L= rows are equalities, L+/L- rows and sign-bound variables orthant rows, Q blocks
// second-order cones, and QR blocks second-order cones after the orthogonal map
// (u, v, w) -> ((u + v)/sqrt 2, (u - v)/sqrt 2, w), which takes QR onto Q. MAX is solved as
// min -c^T x. Integer variables, semidefinite, exponential and power cones (INT, PSDVAR,
// PSDCON, FCOORD, HCOORD, DCOORD, EXP, POW...) are rejected with an error naming the line.
#include <cstdint>
#include <iosfwd>
#include <string>

#include "solvers/conic/ipm_solver.h"

namespace bivo::experiments {

struct CbfProblem {
  solvers::conic::ConicProblem problem;  // the IPM's form; x is the file's x
  bool maximize = false;
  double objective_constant = 0.0;  // c0 (OBJBCOORD)
  // The objective in the file's sense and units, from the IPM form's value.
  double file_objective(double conic_objective) const {
    return (maximize ? -conic_objective : conic_objective) + objective_constant;
  }
};

// Reads, converts and validates (solvers::conic::validate) a CBF file; bivo::Error as
// "<file>:<line>: <what>" on malformed or unsupported input.
CbfProblem read_cbf(const std::string& path);
CbfProblem parse_cbf(std::istream& in, const std::string& name);

// The most variables + constraints (VAR n + CON m) a CBF file may declare. The two headers
// decide allocations of O(n + m) before any entry is read, so a 30-byte file could otherwise
// ask for gigabytes; above the limit the file is refused naming the line, the sizes and the
// flag. Default 2^24 (the paper's VGA SOCP has about 6e5 rows); process-wide, raised with
// `bivo --max-conic-size N`; at most 2^30.
std::int64_t& max_cbf_size();

// True for a path ending in ".cbf" (any case).
bool is_cbf_path(const std::string& path);

}  // namespace bivo::experiments
