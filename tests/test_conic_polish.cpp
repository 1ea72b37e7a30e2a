// Active-set Newton polishing (solvers/conic/polish.h) against closed forms: a boundary cone
// with an equality, an apex cone (s = 0), an orthant vertex; a wrong active-set guess must be
// refused, and the polished and unpolished IPM answers must agree.
#include <cmath>

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "solvers/conic/cones.h"
#include "solvers/conic/constraint_matrix.h"
#include "solvers/conic/ipm_solver.h"
#include "solvers/conic/polish.h"

using namespace bivo::solvers::conic;

namespace {

SparseMatrix sparse(const Eigen::MatrixXd& d) { return d.sparseView(); }

IpmResult solve(const ConicProblem& p, bool polish) {
  IpmSettings st;
  st.polish = polish;
  return solve_conic(p, st);
}

}  // namespace

// min -x2 s.t. x1 = 1/2, ||(x1, x2)|| <= 1: x = (1/2, sqrt(3)/2), the cone on its boundary.
TEST(ConicPolish, BoundaryConeWithEqualityIsClosedForm) {
  ConicProblem p;
  p.c = Eigen::Vector2d(0.0, -1.0);
  p.A = sparse(Eigen::RowVector2d(1.0, 0.0));
  p.b = Eigen::VectorXd::Constant(1, 0.5);
  Eigen::MatrixXd G(3, 2);
  G << 0, 0, -1, 0, 0, -1;  // s = (1, x1, x2)
  p.G = sparse(G);
  p.h = Eigen::Vector3d(1.0, 0.0, 0.0);
  p.cones.soc = {3};
  const IpmResult r = solve(p, true);
  ASSERT_EQ(r.status, IpmStatus::kOptimal);
  EXPECT_TRUE(r.polished);
  EXPECT_NEAR(r.x[0], 0.5, 1e-14);
  EXPECT_NEAR(r.x[1], std::sqrt(0.75), 1e-14);
  // Dual: c + A^T y + G^T z = 0 with z = lambda (1, -x) on the boundary: lambda = 1/x2.
  EXPECT_NEAR(r.z[0], 1.0 / std::sqrt(0.75), 1e-12);
  EXPECT_NEAR(r.s.dot(r.z), 0.0, 1e-14);
}

// min t s.t. ||x - a|| <= t: x = a, t = 0, so s = (t, x - a) = 0 (apex), z interior.
TEST(ConicPolish, ApexConeIsClosedForm) {
  const Eigen::Vector3d a(1.5, -2.0, 0.25);
  ConicProblem p;
  p.c = Eigen::Vector4d(1.0, 0.0, 0.0, 0.0);  // (t, x)
  p.A.resize(0, 4);
  p.b.resize(0);
  p.G = sparse(-Eigen::MatrixXd::Identity(4, 4));
  p.h = Eigen::Vector4d(0.0, -a[0], -a[1], -a[2]);
  p.cones.soc = {4};
  const IpmResult r = solve(p, true);
  ASSERT_EQ(r.status, IpmStatus::kOptimal);
  EXPECT_TRUE(r.polished);
  EXPECT_LT((r.x.tail(3) - a).norm(), 1e-14);
  EXPECT_NEAR(r.x[0], 0.0, 1e-14);
  EXPECT_LT(r.s.norm(), 1e-14);
  EXPECT_NEAR(r.z[0], 1.0, 1e-12);  // G^T z = c: z = (1, 0, 0, 0)
}

// An LP vertex: min -x1 - 2 x2 s.t. x1 + x2 <= 4, x1 - x2 <= 2, x >= 0 -> (0, 4).
TEST(ConicPolish, OrthantVertexIsExact) {
  ConicProblem p;
  p.c = Eigen::Vector2d(-1.0, -2.0);
  p.A.resize(0, 2);
  p.b.resize(0);
  Eigen::MatrixXd G(4, 2);
  G << 1, 1, 1, -1, -1, 0, 0, -1;
  p.G = sparse(G);
  p.h = Eigen::Vector4d(4, 2, 0, 0);
  p.cones.nonnegative = 4;
  const IpmResult r = solve(p, true);
  ASSERT_EQ(r.status, IpmStatus::kOptimal);
  EXPECT_TRUE(r.polished);
  EXPECT_NEAR(r.x[0], 0.0, 1e-15);
  EXPECT_NEAR(r.x[1], 4.0, 1e-14);
  EXPECT_NEAR(r.primal_objective, -8.0, 1e-13);
}

// min x s.t. 1 <= x <= 5 (G = [-1; 1], h = [-1; 5]). An iterate claiming the upper bound is
// active (s2 < z2) makes Newton land on x = 5 with z2 = -1 < 0: refused. The right guess
// (s1 < z1) gives x = 1, z = (1, 0).
TEST(ConicPolish, WrongActiveSetIsRefused) {
  ConicProblem p;
  p.c = Eigen::VectorXd::Ones(1);
  p.A.resize(0, 1);
  p.b.resize(0);
  p.G = sparse(Eigen::Vector2d(-1.0, 1.0));
  p.h = Eigen::Vector2d(-1.0, 5.0);
  p.cones.nonnegative = 2;
  p.G.makeCompressed();
  const ConstraintMatrix G(p.G);
  const ConeProduct K(p.cones);
  Polisher polisher(p, G, K);
  Variables v, out;
  v.resize(1, 0, 2);
  v.tau = 1.0;
  v.x[0] = 4.9;
  v.s = Eigen::Vector2d(3.9, 0.1);
  v.z = Eigen::Vector2d(0.01, 0.5);  // says: upper bound active
  EXPECT_FALSE(polisher.polish(v, out));
  v.x[0] = 1.1;
  v.s = Eigen::Vector2d(0.1, 3.9);
  v.z = Eigen::Vector2d(0.5, 0.01);  // lower bound active
  ASSERT_TRUE(polisher.polish(v, out));
  EXPECT_DOUBLE_EQ(out.x[0], 1.0);
  EXPECT_NEAR(out.z[0], 1.0, 1e-15);
  EXPECT_EQ(out.z[1], 0.0);
  EXPECT_EQ(out.s[0], 0.0);
  EXPECT_NEAR(out.s[1], 4.0, 1e-15);
}

// Projection of a point onto a second-order cone (closed form), with and without polishing:
// the polished answer is at rounding level, the IPM's at its tolerance.
TEST(ConicPolish, SocProjectionPolishedAndPlainAgreeWithClosedForm) {
  const Eigen::Vector3d v(1.0, 2.0, -1.0);  // ||v1|| > v0: projection on the boundary
  const double n1 = v.tail(2).norm();
  Eigen::Vector3d proj;
  proj[0] = 0.5 * (v[0] + n1);
  proj.tail(2) = proj[0] * v.tail(2) / n1;
  // min t s.t. ||x - v|| <= t, x in Q^3: variables (t, x).
  ConicProblem p;
  p.c = Eigen::Vector4d(1.0, 0.0, 0.0, 0.0);
  p.A.resize(0, 4);
  p.b.resize(0);
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(7, 4);
  G.topRows(4) = -Eigen::MatrixXd::Identity(4, 4);
  G.bottomRightCorner(3, 3) = -Eigen::MatrixXd::Identity(3, 3);
  p.G = sparse(G);
  p.h = Eigen::VectorXd::Zero(7);
  p.h.segment(1, 3) = -v;
  p.cones.soc = {4, 3};
  const IpmResult polished = solve(p, true), plain = solve(p, false);
  ASSERT_EQ(polished.status, IpmStatus::kOptimal);
  ASSERT_EQ(plain.status, IpmStatus::kOptimal);
  EXPECT_TRUE(polished.polished);
  EXPECT_FALSE(plain.polished);
  EXPECT_LT((polished.x.tail(3) - proj).norm(), 1e-13);
  EXPECT_LT((plain.x.tail(3) - proj).norm(), 1e-6);
  EXPECT_LT(polished.iterations, plain.iterations);
}
