#pragma once
// The independent re-check of a conic IPM exit from the returned (x, y, z, s) and the data as
// given, with formulas written apart from the solver (dense Eigen, no equilibration):
//   optimal (strict)    primal residual max(||Ax - b|| / max(1, ||b||), ||Gx + s - h|| / max(1, ||h||)),
//                       dual residual ||A'y + G'z + c|| / max(1, ||c||) and the objective gap
//                       |c'x + h'z + b'y| / (1 + |c'x|) all below 1e-8, s and z in K;
//   optimal (reduced)   the note says which strict tolerance fails;
//   primal infeasible   h'z + b'y = -1, ||A'y + G'z|| below 1e-8, z in K;
//   dual infeasible     c'x = -1, ||A x|| and ||G x + s|| below 1e-8, s in K.
// Shared by test_conic_exit_certificates (generated families) and test_conic_suite (the public
// problems).
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "solvers/conic/ipm_solver.h"

namespace bivo::solvers::conic::testing {

// Slack for summation order only: the solver certifies at 1e-8 with its own sums.
inline constexpr double kExitTol = 1e-8 * (1.0 + 1e-6);

inline double min_eig(const ConeSpec& cones, const Eigen::VectorXd& u) {
  double e = std::numeric_limits<double>::infinity();
  for (int i = 0; i < cones.nonnegative; ++i) e = std::min(e, u[i]);
  int o = cones.nonnegative;
  for (const int d : cones.soc) {
    e = std::min(e, u[o] - u.segment(o + 1, d - 1).norm());
    o += d;
  }
  return u.size() ? e / (1.0 + u.cwiseAbs().maxCoeff()) : 0.0;
}

struct ExitTally {
  int optimal = 0, reduced = 0, infeasible = 0, other = 0;
};

// The independent check of one exit; counts it in t.
inline void check_exit(const ConicProblem& p, const IpmResult& r, const std::string& what, ExitTally& t) {
  const Eigen::MatrixXd G = p.has_dense_G() ? p.dense_G : Eigen::MatrixXd(p.G);
  const Eigen::MatrixXd A = Eigen::MatrixXd(p.A);
  const bool eq = p.b.size() > 0;
  const double kTol = kExitTol;
  ASSERT_EQ(r.x.size(), p.c.size()) << what;
  ASSERT_EQ(r.z.size(), p.h.size()) << what;
  ASSERT_TRUE(r.x.allFinite() && r.y.allFinite() && r.z.allFinite() && r.s.allFinite()) << what;
  if (r.status == IpmStatus::kOptimal && r.reduced_accuracy) {
    ++t.reduced;
    EXPECT_FALSE(r.note.empty()) << what << ": a reduced-accuracy exit says which tolerance fails";
    return;
  }
  if (r.status == IpmStatus::kOptimal) {
    ++t.optimal;
    const double pa = eq ? (A * r.x - p.b).norm() / std::max(1.0, p.b.norm()) : 0.0;
    const double pg = (G * r.x + r.s - p.h).norm() / std::max(1.0, p.h.norm());
    Eigen::VectorXd d = G.transpose() * r.z + p.c;
    if (eq) d += A.transpose() * r.y;
    const double cx = p.c.dot(r.x);
    const double gap = std::abs(cx + p.h.dot(r.z) + (eq ? p.b.dot(r.y) : 0.0)) / (1.0 + std::abs(cx));
    EXPECT_LT(std::max(pa, pg), kTol) << what << ": primal residual";
    EXPECT_LT(d.norm() / std::max(1.0, p.c.norm()), kTol) << what << ": dual residual";
    EXPECT_LT(gap, kTol) << what << ": objective gap";
    EXPECT_GE(min_eig(p.cones, r.s), -kTol) << what << ": s outside K";
    EXPECT_GE(min_eig(p.cones, r.z), -kTol) << what << ": z outside K";
    return;
  }
  if (r.status == IpmStatus::kPrimalInfeasible) {
    ++t.infeasible;
    Eigen::VectorXd d = G.transpose() * r.z;
    if (eq) d += A.transpose() * r.y;
    EXPECT_NEAR(p.h.dot(r.z) + (eq ? p.b.dot(r.y) : 0.0), -1.0, 1e-9) << what;
    EXPECT_LT(d.norm(), kTol * std::max(1.0, p.c.norm())) << what;
    EXPECT_GE(min_eig(p.cones, r.z), -kTol) << what;
    return;
  }
  if (r.status == IpmStatus::kDualInfeasible) {
    ++t.infeasible;
    EXPECT_NEAR(p.c.dot(r.x), -1.0, 1e-9) << what;
    if (eq) {
      EXPECT_LT((A * r.x).norm(), kTol * std::max(1.0, p.b.norm())) << what;
    }
    EXPECT_LT((G * r.x + r.s).norm(), kTol * std::max(1.0, p.h.norm())) << what;
    EXPECT_GE(min_eig(p.cones, r.s), -kTol) << what;
    return;
  }
  ++t.other;  // max iterations / numerical trouble claim nothing
}

}  // namespace bivo::solvers::conic::testing
