// Huge and "infinite" bounds in the conic IPM: problems whose optimum is known in closed form
// (or from an independent LP solver, as stated per case), with redundant bounds x <= B added.
// For B = 1e12 ... 1e19 the bound is a real, finite constraint: the problem must be solved
// right (never "optimal" at a wrong point, never refused); for B = 1e20, 1e30 the rows are
// absent bounds, removed before the solve and restored with z = 0, s = h - G x.
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "solvers/conic/ipm_solver.h"

using namespace bivo::solvers::conic;

namespace {

const double kFinite[] = {1e12, 1e15, 1e18, 1e19};
const double kInfinite[] = {1e20, 1e30};

ConicProblem make(const Eigen::VectorXd& c, const Eigen::MatrixXd& G, const Eigen::VectorXd& h, ConeSpec cones) {
  ConicProblem p;
  p.c = c;
  p.G = G.sparseView();
  p.h = h;
  p.cones = std::move(cones);
  p.A.resize(0, c.size());
  p.b.resize(0);
  return p;
}

IpmResult solve(const ConicProblem& p, bool polish) {
  IpmSettings s;
  s.polish = polish;
  return solve_conic(p, s);
}

// The status must be a clean optimum at the known point, or (without polishing only, where
// rounding next to a 1e19 row can stall the interior point) an optimum flagged as reduced
// accuracy that is still right to 1e-7. "optimal" at a wrong point fails either way.
void expect_solved(const IpmResult& r, double objective, const Eigen::VectorXd& x, bool polish,
                   const std::string& what) {
  ASSERT_EQ(r.status, IpmStatus::kOptimal) << what << ": " << status_text(r);
  if (polish) {
    EXPECT_FALSE(r.reduced_accuracy) << what << ": " << status_text(r);
  }
  const double tol = r.reduced_accuracy ? 1e-7 : 1e-8;
  EXPECT_NEAR(r.primal_objective, objective, tol * (1.0 + std::abs(objective))) << what;
  EXPECT_LT((r.x - x).norm(), 1e-6 * (1.0 + x.norm())) << what << ": x = " << r.x.transpose();
}

std::string name(const char* what, double bound, bool polish) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%s, bound %.0e, %s", what, bound, polish ? "polished" : "no polish");
  return buf;
}

}  // namespace

// min x s.t. x >= 2, x <= B: optimum 2 at x = 2 (closed form). This exact problem with
// B = 1e20 was reported optimal at x = 0: the polished point's residual measured against
// ||h|| = 1e20 and no comparison of the primal and dual objectives.
TEST(ConicInfiniteBounds, OneVariableLowerBoundIsActive) {
  Eigen::MatrixXd G(2, 1);
  G << -1, 1;
  for (const bool polish : {true, false}) {
    for (const double B : kFinite) {
      const IpmResult r = solve(make(Eigen::VectorXd::Ones(1), G, Eigen::Vector2d(-2, B), {2, {}}), polish);
      expect_solved(r, 2.0, Eigen::VectorXd::Constant(1, 2.0), polish, name("min x, x >= 2", B, polish));
      EXPECT_EQ(r.infinite_rows, 0);
    }
    for (const double B : kInfinite) {
      const IpmResult r = solve(make(Eigen::VectorXd::Ones(1), G, Eigen::Vector2d(-2, B), {2, {}}), polish);
      expect_solved(r, 2.0, Eigen::VectorXd::Constant(1, 2.0), polish, name("min x, x >= 2", B, polish));
      EXPECT_EQ(r.infinite_rows, 1);
      ASSERT_EQ(r.z.size(), 2);
      EXPECT_EQ(r.z[1], 0.0);          // the absent bound's multiplier
      EXPECT_NEAR(r.z[0], 1.0, 1e-8);  // the active one's: c = z0
      EXPECT_EQ(r.s[1], B - r.x[0]);   // its slack, h - G x
    }
  }
}

// max x1 + x2 + x3 s.t. x1 + x2 + x3 <= 1.5, 0 <= x <= 1, x <= B: optimum -1.5 (closed form;
// the optimal set is a face, so only the objective and feasibility are checked).
TEST(ConicInfiniteBounds, ThreeVariableLpWithABoundPerVariable) {
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(10, 3);
  G.row(0) << 1, 1, 1;
  for (int i = 0; i < 3; ++i) G(1 + i, i) = -1, G(4 + i, i) = 1, G(7 + i, i) = 1;
  for (const bool polish : {true, false}) {
    for (const double B : {1e12, 1e15, 1e18, 1e19, 1e20, 1e30}) {
      Eigen::VectorXd h(10);
      h << 1.5, 0, 0, 0, 1, 1, 1, B, B, B;
      const IpmResult r = solve(make(-Eigen::VectorXd::Ones(3), G, h, {10, {}}), polish);
      const std::string what = name("3-variable LP", B, polish);
      ASSERT_EQ(r.status, IpmStatus::kOptimal) << what << ": " << status_text(r);
      EXPECT_NEAR(r.primal_objective, -1.5, 1e-7) << what;
      EXPECT_LE(r.x.sum(), 1.5 + 1e-8) << what;
      EXPECT_GE(r.x.minCoeff(), -1e-8) << what;
      EXPECT_LE(r.x.maxCoeff(), 1.0 + 1e-8) << what;
      EXPECT_EQ(r.infinite_rows, B >= 1e20 ? 3 : 0) << what;
    }
  }
}

// min -2 x1 - 3 x2 - x3 s.t. x1 + x2 + x3 <= 4, x1 + 3 x2 <= 6, 3 x1 + x3 <= 5, x >= 0,
// x <= B: the three rows are active at x = (9, 11, 8) / 7, objective -59/7 (closed form;
// scipy.optimize.linprog with HiGHS gives -8.428571428571429 at the same x).
TEST(ConicInfiniteBounds, LpWithThreeActiveRows) {
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(9, 3);
  G.topRows(3) << 1, 1, 1, 1, 3, 0, 3, 0, 1;
  for (int i = 0; i < 3; ++i) G(3 + i, i) = -1, G(6 + i, i) = 1;
  const Eigen::Vector3d x_star(9.0 / 7, 11.0 / 7, 8.0 / 7);
  for (const bool polish : {true, false}) {
    for (const double B : {1e12, 1e15, 1e18, 1e19, 1e20, 1e30}) {
      Eigen::VectorXd h(9);
      h << 4, 6, 5, 0, 0, 0, B, B, B;
      const IpmResult r = solve(make(Eigen::Vector3d(-2, -3, -1), G, h, {9, {}}), polish);
      expect_solved(r, -59.0 / 7.0, x_star, polish, name("LP, 3 active rows", B, polish));
    }
  }
}

// max x s.t. 0 <= x <= B: a finite bound is the optimum itself (-B at x = B); an infinite
// one is absent, so the problem is unbounded, certified by a ray with c'x = -1.
TEST(ConicInfiniteBounds, HugeBoundAtTheOptimumOrUnbounded) {
  Eigen::MatrixXd G(2, 1);
  G << -1, 1;
  for (const bool polish : {true, false}) {
    for (const double B : kFinite) {
      const IpmResult r = solve(make(-Eigen::VectorXd::Ones(1), G, Eigen::Vector2d(0, B), {2, {}}), polish);
      expect_solved(r, -B, Eigen::VectorXd::Constant(1, B), polish, name("max x, x <= B", B, polish));
    }
    for (const double B : kInfinite) {
      const IpmResult r = solve(make(-Eigen::VectorXd::Ones(1), G, Eigen::Vector2d(0, B), {2, {}}), polish);
      ASSERT_EQ(r.status, IpmStatus::kDualInfeasible) << status_text(r);
      EXPECT_NEAR(r.x[0], 1.0, 1e-8);  // c'x = -1 and G_0 x + s_0 = 0 with s_0 >= 0
      EXPECT_EQ(r.infinite_rows, 1);
    }
  }
}

// min t s.t. ||(x1 - 3, x2 - 4)|| <= t, x1 <= 1, x2 <= B, -x1 <= B: the nearest point of
// {x1 <= 1} to (3, 4) is (1, 4), distance 2 (closed form). With B = 1e18 and polishing, the
// first polished guess here was (t, x) = 0 with the cone violated by 5, which ||h|| = 1.4e18
// excused: the block-by-block primal residual refuses it.
TEST(ConicInfiniteBounds, SocpDistanceToAHalfPlane) {
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(6, 3);
  G(0, 1) = 1, G(1, 2) = 1, G(2, 1) = -1;
  G(3, 0) = -1, G(4, 1) = -1, G(5, 2) = -1;
  for (const bool polish : {true, false}) {
    for (const double B : {1e12, 1e15, 1e18, 1e19, 1e20, 1e30}) {
      Eigen::VectorXd h(6);
      h << 1, B, B, 0, -3, -4;
      const IpmResult r = solve(make(Eigen::Vector3d(1, 0, 0), G, h, {3, {3}}), polish);
      expect_solved(r, 2.0, Eigen::Vector3d(2, 1, 4), polish, name("SOCP distance", B, polish));
      EXPECT_EQ(r.infinite_rows, B >= 1e20 ? 2 : 0);
    }
  }
}

// min x1 + x2 s.t. ||x|| <= 1, ||x|| <= B (a second cone), x <= B: -sqrt(2) at -(1, 1)/sqrt(2)
// (closed form). From 1e20 the second cone (head B, tail finite) goes as a whole, its z = 0.
TEST(ConicInfiniteBounds, SocpWholeConeWithAnInfiniteHead) {
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(8, 2);
  G(0, 0) = 1, G(1, 1) = 1, G(3, 0) = -1, G(4, 1) = -1, G(6, 0) = -1, G(7, 1) = -1;
  const Eigen::Vector2d x_star = -Eigen::Vector2d::Ones() / std::sqrt(2.0);
  for (const bool polish : {true, false}) {
    for (const double B : {1e12, 1e15, 1e18, 1e19, 1e20, 1e30}) {
      Eigen::VectorXd h(8);
      h << B, B, 1, 0, 0, B, 0, 0;
      const IpmResult r = solve(make(Eigen::Vector2d(1, 1), G, h, {2, {3, 3}}), polish);
      expect_solved(r, -std::sqrt(2.0), x_star, polish, name("SOCP disc", B, polish));
      EXPECT_EQ(r.infinite_rows, B >= 1e20 ? 5 : 0);
      if (B >= 1e20) {
        EXPECT_EQ(r.z.tail(3).norm(), 0.0);
        EXPECT_EQ(r.s[5], B - 0.0);  // head: h - G x, G's head row is 0
        EXPECT_NEAR(r.s[6], x_star[0], 1e-8);
      }
    }
  }
}

// What is NOT an absent bound stays: a cone with a huge tail entry, a row with h <= -B.
TEST(ConicInfiniteBounds, HugeNegativeRowsAndConeTailsAreKept) {
  // max x s.t. x <= -1e20: the optimum is x = -1e20 itself.
  const IpmResult r = solve(
      make(-Eigen::VectorXd::Ones(1), Eigen::MatrixXd::Ones(1, 1), Eigen::VectorXd::Constant(1, -1e20), {1, {}}), true);
  EXPECT_EQ(r.infinite_rows, 0);
  if (r.status == IpmStatus::kOptimal) {
    EXPECT_NEAR(r.x[0], -1e20, 1e12) << status_text(r);
  }
  // min t s.t. |x - 1e20| <= t, t <= 1e25: the orthant row is an absent bound, the cone (its
  // head 0, its tail -1e20) a real constraint; optimum t = 0 at x = 1e20.
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(3, 2);
  G(0, 0) = 1, G(1, 0) = -1, G(2, 1) = -1;
  Eigen::Vector3d h(1e25, 0, -1e20);
  const IpmResult q = solve(make(Eigen::Vector2d(1, 0), G, h, {1, {2}}), true);
  EXPECT_EQ(q.infinite_rows, 1);
  ASSERT_EQ(q.z.size(), 3);
  EXPECT_EQ(q.z[0], 0.0);
  EXPECT_NE(q.status, IpmStatus::kDualInfeasible) << status_text(q);
  if (q.status == IpmStatus::kOptimal) {
    EXPECT_NEAR(q.x[1], 1e20, 1e12) << status_text(q);
  }
}

// The setting: infinity = +inf keeps every row (the 1e20 row then is a finite bound, solved).
TEST(ConicInfiniteBounds, ThresholdIsASetting) {
  Eigen::MatrixXd G(2, 1);
  G << -1, 1;
  const ConicProblem p = make(Eigen::VectorXd::Ones(1), G, Eigen::Vector2d(-2, 1e20), {2, {}});
  IpmSettings s;
  s.infinity = std::numeric_limits<double>::infinity();
  const IpmResult kept = solve_conic(p, s);
  EXPECT_EQ(kept.infinite_rows, 0);
  expect_solved(kept, 2.0, Eigen::VectorXd::Constant(1, 2.0), true, "no presolve");
  s.infinity = 1e19;
  const IpmResult lower = solve_conic(make(Eigen::VectorXd::Ones(1), G, Eigen::Vector2d(-2, 1e19), {2, {}}), s);
  EXPECT_EQ(lower.infinite_rows, 1);
  expect_solved(lower, 2.0, Eigen::VectorXd::Constant(1, 2.0), true, "threshold 1e19");
}

// The reported example end to end through `bivo conic`.
TEST(ConicInfiniteBounds, CommandLineExample) {
  const std::string path = ::testing::TempDir() + "infinite_bound.json";
  std::ofstream(path) << R"({"c":[1],"G":[[-1],[1]],"h":[-2,1e20],"cones":{"l":2,"q":[]}})";
  for (const std::string flags : {"", " --no-polish"}) {
    FILE* pipe = popen((std::string(BIVO_BINARY) + " conic " + path + flags + " --solution 2>&1").c_str(), "r");
    ASSERT_NE(pipe, nullptr);
    std::string out;
    char buf[512];
    while (fgets(buf, sizeof buf, pipe)) out += buf;
    EXPECT_EQ(WEXITSTATUS(pclose(pipe)), 0) << out;
    EXPECT_NE(out.find("status: optimal\n"), std::string::npos) << out;
    const auto k = out.find("objective: ");
    ASSERT_NE(k, std::string::npos) << out;
    EXPECT_NEAR(std::stod(out.substr(k + 11)), 2.0, 1e-8) << out;
    EXPECT_NE(out.find("infinite bounds: 1 rows removed"), std::string::npos) << out;
  }
}
