#include "odometry/io/timestamp_matching.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <sstream>
#include <tuple>

#include "solvers/error.h"

namespace bivo::odometry::io {
namespace {

void require_strictly_increasing(const std::vector<double>& v, const char* name) {
  for (std::size_t k = 1; k < v.size(); ++k) {
    if (!(v[k - 1] < v[k])) {
      std::ostringstream m;
      m.precision(17);
      m << "associate_timestamps: stamps of list " << name << " must be strictly increasing, but entry " << k << " ("
        << v[k] << ") follows " << v[k - 1];
      throw Error(m.str());
    }
  }
}

}  // namespace

std::vector<std::pair<int, int>> associate_timestamps(const std::vector<double>& a, const std::vector<double>& b,
                                                      double max_dt) {
  require_strictly_increasing(a, "a");
  require_strictly_increasing(b, "b");
  if (a.size() > static_cast<std::size_t>(std::numeric_limits<int>::max() / 2) ||
      b.size() > static_cast<std::size_t>(std::numeric_limits<int>::max() / 2)) {
    throw Error("associate_timestamps: lists too long to index");
  }
  // Merged order of both lists; node k < n is a[k], node n + k is b[k]. Equal stamps of the
  // two lists end up adjacent (each list has distinct stamps).
  const int n = static_cast<int>(a.size()), m = static_cast<int>(b.size());
  std::vector<int> order;
  order.reserve(static_cast<std::size_t>(n) + m);
  for (int i = 0, j = 0; i < n || j < m;) {
    if (j == m || (i < n && a[i] <= b[j]))
      order.push_back(i++);
    else
      order.push_back(n + j++);
  }
  // Doubly linked list of the unmatched nodes in merged order (-1: none).
  std::vector<int> prev(order.size()), next(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    prev[order[k]] = k == 0 ? -1 : order[k - 1];
    next[order[k]] = k + 1 == order.size() ? -1 : order[k + 1];
  }
  using Candidate = std::tuple<double, int, int>;  // (|a_i - b_j|, i, j): the definition's sort key
  std::priority_queue<Candidate, std::vector<Candidate>, std::greater<Candidate>> queue;
  const auto offer = [&](int x, int y) {  // x, y adjacent nodes
    if (x < 0 || y < 0 || (x < n) == (y < n)) return;
    const int i = std::min(x, y), j = std::max(x, y) - n;
    const double d = std::abs(a[i] - b[j]);
    if (d < max_dt) queue.emplace(d, i, j);
  };
  for (std::size_t k = 0; k + 1 < order.size(); ++k) offer(order[k], order[k + 1]);

  std::vector<char> used_a(a.size(), 0), used_b(b.size(), 0);
  std::vector<std::pair<int, int>> matches;
  while (!queue.empty()) {
    const auto [d, i, j] = queue.top();
    queue.pop();
    (void)d;
    if (used_a[i] || used_b[j]) continue;  // queued while adjacent; both unmatched => still adjacent
    used_a[i] = used_b[j] = 1;
    matches.emplace_back(i, j);
    // Unlink both nodes; their outer neighbours become adjacent.
    const bool a_left = next[i] == n + j;
    const int x = a_left ? i : n + j, y = a_left ? n + j : i;
    const int before = prev[x], after = next[y];
    if (before >= 0) next[before] = after;
    if (after >= 0) prev[after] = before;
    offer(before, after);
  }
  std::sort(matches.begin(), matches.end());
  return matches;
}

}  // namespace bivo::odometry::io
