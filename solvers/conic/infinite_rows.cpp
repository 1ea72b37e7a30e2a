#include "solvers/conic/infinite_rows.h"

#include <cmath>
#include <limits>

namespace bivo::solvers::conic {

bool remove_infinite_rows(const ConicProblem& p, double threshold, InfiniteRows& out) {
  if (!(threshold < std::numeric_limits<double>::infinity())) return false;
  const int l = p.cones.nonnegative, m = p.num_cone_rows();
  std::vector<char> keep(static_cast<size_t>(m), 1);
  int removed = 0;
  ConeSpec cones;
  for (int i = 0; i < l; ++i) {
    if (p.h[i] >= threshold) {
      keep[i] = 0;
      ++removed;
    }
  }
  cones.nonnegative = l - removed;
  int offset = l;
  for (const int d : p.cones.soc) {
    bool vacuous = p.h[offset] >= threshold;
    for (int i = 1; i < d && vacuous; ++i) vacuous = std::abs(p.h[offset + i]) < threshold;
    if (vacuous) {
      for (int i = 0; i < d; ++i) keep[offset + i] = 0;
      removed += d;
    } else {
      cones.soc.push_back(d);
    }
    offset += d;
  }
  if (removed == 0) return false;
  out.removed = removed;
  out.kept.clear();
  for (int i = 0; i < m; ++i)
    if (keep[i]) out.kept.push_back(i);
  const int mk = static_cast<int>(out.kept.size()), n = p.num_variables();
  ConicProblem& r = out.reduced;
  r.c = p.c;
  r.A = p.A;
  r.b = p.b;
  r.cones = cones;
  r.h.resize(mk);
  for (int i = 0; i < mk; ++i) r.h[i] = p.h[out.kept[i]];
  r.G = SparseMatrix();
  r.dense_G.resize(0, 0);
  if (p.has_dense_G()) {
    // A dense G with every row removed stays 0 x 0 (validate: a dense G has rows).
    if (mk > 0) r.dense_G = p.dense_G(out.kept, Eigen::all);
  } else if (p.G.cols() == n) {
    SparseMatrix select(mk, m);
    std::vector<Eigen::Triplet<double>> ones;
    ones.reserve(out.kept.size());
    for (int i = 0; i < mk; ++i) ones.emplace_back(i, out.kept[i], 1.0);
    select.setFromTriplets(ones.begin(), ones.end());
    r.G = select * p.G;
  }
  if (r.G.rows() == 0 && r.dense_G.size() == 0) r.G.resize(0, mk > 0 ? n : 0);
  return true;
}

void restore_infinite_rows(const ConicProblem& p, const InfiniteRows& rows, IpmResult& r) {
  const int m = p.num_cone_rows(), n = p.num_variables();
  Eigen::VectorXd gx = Eigen::VectorXd::Zero(m);
  if (r.x.size() == n) {
    if (p.has_dense_G()) {
      gx.noalias() = p.dense_G * r.x;
    } else if (p.G.cols() == n) {
      gx.noalias() = p.G * r.x;
    }
  }
  Eigen::VectorXd s(m), z = Eigen::VectorXd::Zero(m);
  // The removed rows' slack: h - G x at a solution, -G x along an unboundedness ray, 0 in a
  // primal infeasibility certificate (which has x = 0).
  const double h_weight = r.status == IpmStatus::kDualInfeasible ? 0.0 : 1.0;
  if (r.status == IpmStatus::kPrimalInfeasible) {
    s.setZero();
  } else {
    s = h_weight * p.h - gx;
  }
  const int mk = static_cast<int>(rows.kept.size());
  for (int i = 0; i < mk && i < r.s.size(); ++i) {
    s[rows.kept[i]] = r.s[i];
    z[rows.kept[i]] = r.z[i];
  }
  r.s = std::move(s);
  r.z = std::move(z);
  r.infinite_rows = rows.removed;
}

}  // namespace bivo::solvers::conic
