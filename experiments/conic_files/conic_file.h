#pragma once
// Conic programs from files for `bivo conic` (and anyone else): the JSON format of
// docs/conic.md, and the text summary `bivo conic` prints of a solve.
//   {"c": [..n..],
//    "A": <matrix p x n> (optional), "b": [..p..] (optional),
//    "G": <matrix m x n>, "h": [..m..],
//    "cones": {"l": <orthant dim>, "q": [<soc dims>...]}}
// <matrix> is either dense rows [[...], ...] or {"rows": r, "cols": c, "triplets": [[i, j, v], ...]}
// (0-based, duplicates summed).
#include <string>

#include "solvers/conic/ipm_solver.h"

namespace bivo::experiments {

// Reads and validates (solvers::conic::validate) a JSON conic program; bivo::Error names the
// file and the field at fault.
solvers::conic::ConicProblem read_conic_json(const std::string& path);

// status, objective, residuals, iterations, time; with `solution` also x, y, z, s.
std::string conic_result_text(const solvers::conic::IpmResult& result, bool solution);

}  // namespace bivo::experiments
