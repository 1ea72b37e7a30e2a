#pragma once
// One-to-one association of two timestamp lists, as TUM's associate.py (and evaluate_ate.py's
// associate()): rgb with depth frames, estimate with ground-truth poses.
#include <utility>
#include <vector>

namespace bivo::odometry::io {

// Greedy matching: of all pairs (i, j) with |a_i - b_j| < max_dt, take them in order of
// increasing difference (ties: smaller i, then smaller j), each stamp used at most once.
// Returns the (index into a, index into b) pairs sorted by a's timestamp. Both lists must be
// strictly increasing (bivo::Error otherwise; the readers guarantee it).
//
// The globally nearest unmatched pair is always adjacent in the merged order of the stamps
// still unmatched, so only adjacent pairs are ever queued: memory O(n + m) and time
// O((n + m) log(n + m)) whatever max_dt is, where listing every candidate pair would be
// quadratic in a huge max_dt. The result equals the candidate-sorting definition except for
// differences that tie only after rounding (equal to within one ulp).
std::vector<std::pair<int, int>> associate_timestamps(const std::vector<double>& a, const std::vector<double>& b,
                                                      double max_dt);

}  // namespace bivo::odometry::io
