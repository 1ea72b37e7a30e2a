#pragma once
// Bounds written as "infinite" (1e20, 1e30: how modelling tools say "no bound") set aside
// before the solve, as Clarabel's presolve does. Left in, such a row makes ||h|| ~ 1e20, so
// every residual measured relative to it passes, and equilibration scales the real rows to
// nothing. Removed:
//   * an orthant row with h_i >= threshold (G_i x <= +inf holds for every finite x);
//   * a whole second-order cone whose head h_0 >= threshold while every tail |h_i| is below
//     it (h_0 - G_0 x >= ||h_1 - G_1 x|| then holds for every finite x). A cone with a huge
//     tail entry is a real constraint and is kept, as is any row with h <= -threshold and
//     every equality (A x = b with a huge b is a constraint, not an absent bound).
// The result is restored to the original rows: z = 0 and s = h - G x on a removed row (for a
// dual infeasibility certificate s = -G x, for a primal one s = 0); its measures and status
// stay those of the reduced problem, the one the rows' absence defines.
#include <vector>

#include "solvers/conic/ipm_solver.h"
#include "solvers/conic/problem_data.h"

namespace bivo::solvers::conic {

struct InfiniteRows {
  ConicProblem reduced;
  std::vector<int> kept;  // rows of the original G kept, in order
  int removed = 0;
};

// Fills `out` and returns true when some row is removed; false (out untouched) otherwise.
bool remove_infinite_rows(const ConicProblem& problem, double threshold, InfiniteRows& out);

// The reduced problem's result in the original rows (see above); sets result.infinite_rows.
void restore_infinite_rows(const ConicProblem& original, const InfiniteRows& rows, IpmResult& result);

}  // namespace bivo::solvers::conic
