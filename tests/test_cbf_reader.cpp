// The CBF reader (experiments/conic_files/cbf_file.h) on hand-written instances whose optima are known in
// closed form (one per cone kind, in VAR and in CON, MIN and MAX, the objective constant),
// infeasible and unbounded ones (the IPM's certificates checked), and malformed files (the
// error names the file and the line).
#include <cmath>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "experiments/conic_files/cbf_file.h"
#include "solvers/error.h"

namespace {

using bivo::experiments::CbfProblem;
using bivo::experiments::parse_cbf;
using bivo::solvers::conic::IpmResult;
using bivo::solvers::conic::IpmStatus;
using bivo::solvers::conic::solve_conic;

CbfProblem parse(const std::string& text) {
  std::istringstream in(text);
  return parse_cbf(in, "test.cbf");
}

struct Solved {
  CbfProblem p;
  IpmResult r;
  double objective() const { return p.file_objective(r.primal_objective); }
};

Solved solve(const std::string& text) {
  Solved s{parse(text), {}};
  s.r = solve_conic(s.p.problem);
  return s;
}

}  // namespace

TEST(CbfReader, LinearConesInVarAndCon) {
  // min x0 + x1 s.t. x0 + 2 x1 - 2 >= 0, x >= 0: x = (0, 1), objective 1 (+ constant 0.5).
  const Solved s = solve(
      "# a comment\nVER\n4\n\nOBJSENSE\nMIN\n\nVAR\n2 1\nL+ 2\n\nCON\n1 1\nL+ 1\n\n"
      "OBJACOORD\n2\n0 1\n1 1\n\nOBJBCOORD\n0.5\n\nACOORD\n2\n0 0 1\n0 1 2\n\nBCOORD\n1\n0 -2\n");
  ASSERT_EQ(s.r.status, IpmStatus::kOptimal);
  EXPECT_NEAR(s.objective(), 1.5, 1e-8);
  EXPECT_NEAR(s.r.x[0], 0.0, 1e-7);
  EXPECT_NEAR(s.r.x[1], 1.0, 1e-7);
}

TEST(CbfReader, EqualityNonpositiveAndMax) {
  // max x0 + x1 s.t. x0 - x1 = 0 (L=), x0 + x1 - 2 <= 0 (L-), x free: 2 at x = (1, 1).
  const Solved s = solve(
      "VER\n3\nOBJSENSE\nMAX\nVAR\n2 1\nF 2\nCON\n2 2\nL= 1\nL- 1\n"
      "OBJACOORD\n2\n0 1\n1 1\nACOORD\n4\n0 0 1\n0 1 -1\n1 0 1\n1 1 1\nBCOORD\n1\n1 -2\n");
  ASSERT_EQ(s.r.status, IpmStatus::kOptimal);
  EXPECT_TRUE(s.p.maximize);
  EXPECT_NEAR(s.objective(), 2.0, 1e-8);
  EXPECT_NEAR(s.r.x[0], 1.0, 1e-7);
  EXPECT_NEAR(s.r.x[1], 1.0, 1e-7);
  // A nonpositive variable: min x0 s.t. x0 in L-, x0 + 3 >= 0: -3.
  const Solved neg = solve(
      "VER\n4\nOBJSENSE\nMIN\nVAR\n1 1\nL- 1\nCON\n1 1\nL+ 1\nOBJACOORD\n1\n0 1\n"
      "ACOORD\n1\n0 0 1\nBCOORD\n1\n0 3\n");
  ASSERT_EQ(neg.r.status, IpmStatus::kOptimal);
  EXPECT_NEAR(neg.objective(), -3.0, 1e-8);
}

TEST(CbfReader, QuadraticConeInVarAndCon) {
  // min x0 s.t. x in Q^3, x1 = 3, x2 = 4: 5.
  const Solved var = solve(
      "VER\n4\nOBJSENSE\nMIN\nVAR\n3 1\nQ 3\nCON\n2 1\nL= 2\nOBJACOORD\n1\n0 1\n"
      "ACOORD\n2\n0 1 1\n1 2 1\nBCOORD\n2\n0 -3\n1 -4\n");
  ASSERT_EQ(var.r.status, IpmStatus::kOptimal);
  EXPECT_NEAR(var.objective(), 5.0, 1e-8);
  // min t s.t. (t, x1 - 3, x2 - 4) in Q^3 (CON), x1 + x2 = 1: 6/sqrt(2) (distance to the line).
  const Solved con = solve(
      "VER\n4\nOBJSENSE\nMIN\nVAR\n3 1\nF 3\nCON\n4 2\nQ 3\nL= 1\nOBJACOORD\n1\n0 1\n"
      "ACOORD\n5\n0 0 1\n1 1 1\n2 2 1\n3 1 1\n3 2 1\nBCOORD\n3\n1 -3\n2 -4\n3 -1\n");
  ASSERT_EQ(con.r.status, IpmStatus::kOptimal);
  EXPECT_NEAR(con.objective(), 6.0 / std::sqrt(2.0), 1e-8);
  EXPECT_NEAR(con.r.x[1] + con.r.x[2], 1.0, 1e-8);
}

TEST(CbfReader, RotatedQuadraticConeInVarAndCon) {
  // min x0 + x1 s.t. (x0, x1, x2) in QR^3 (2 x0 x1 >= x2^2), x2 = 2: x0 = x1 = sqrt 2, 2 sqrt 2.
  const Solved var = solve(
      "VER\n4\nOBJSENSE\nMIN\nVAR\n3 1\nQR 3\nCON\n1 1\nL= 1\nOBJACOORD\n2\n0 1\n1 1\n"
      "ACOORD\n1\n0 2 1\nBCOORD\n1\n0 -2\n");
  ASSERT_EQ(var.r.status, IpmStatus::kOptimal);
  EXPECT_NEAR(var.objective(), 2.0 * std::sqrt(2.0), 1e-8);
  EXPECT_NEAR(var.r.x[0], std::sqrt(2.0), 1e-6);
  EXPECT_NEAR(var.r.x[1], std::sqrt(2.0), 1e-6);
  // The same cone on constraint rows (u, v, w) = (x0, 2 x1, 2): 4 x0 x1 >= 4, min x0 + 2 x1 ->
  // x0 = sqrt 2, x1 = 1/sqrt 2, objective 2 sqrt 2; the asymmetric 2 checks the row map.
  const Solved con = solve(
      "VER\n4\nOBJSENSE\nMIN\nVAR\n2 1\nF 2\nCON\n3 1\nQR 3\nOBJACOORD\n2\n0 1\n1 2\n"
      "ACOORD\n2\n0 0 1\n1 1 2\nBCOORD\n1\n2 2\n");
  ASSERT_EQ(con.r.status, IpmStatus::kOptimal);
  EXPECT_NEAR(con.objective(), 2.0 * std::sqrt(2.0), 1e-8);
  EXPECT_NEAR(con.r.x[0], std::sqrt(2.0), 1e-6);
  EXPECT_NEAR(con.r.x[1], 1.0 / std::sqrt(2.0), 1e-6);
}

TEST(CbfReader, InfeasibleAndUnboundedAreCertified) {
  // x0 - 1 >= 0 and x0 <= 0: primal infeasible; certificate h^T z + b^T y = -1, G^T z + A^T y = 0, z >= 0.
  const Solved inf = solve(
      "VER\n4\nOBJSENSE\nMIN\nVAR\n1 1\nF 1\nCON\n2 2\nL+ 1\nL- 1\nOBJACOORD\n1\n0 1\n"
      "ACOORD\n2\n0 0 1\n1 0 1\nBCOORD\n1\n0 -1\n");
  ASSERT_EQ(inf.r.status, IpmStatus::kPrimalInfeasible);
  const auto& q = inf.p.problem;
  EXPECT_NEAR(q.h.dot(inf.r.z), -1.0, 1e-8);
  EXPECT_LT((q.G.transpose() * inf.r.z).norm(), 1e-8);
  EXPECT_GE(inf.r.z.minCoeff(), -1e-12);
  // min x0 s.t. x0 <= 1 (x0 - 1 in L-), free: unbounded; certificate c^T x = -1, G x + s = 0, s >= 0.
  const Solved unb = solve(
      "VER\n4\nOBJSENSE\nMIN\nVAR\n1 1\nF 1\nCON\n1 1\nL- 1\nOBJACOORD\n1\n0 1\n"
      "ACOORD\n1\n0 0 1\nBCOORD\n1\n0 -1\n");
  ASSERT_EQ(unb.r.status, IpmStatus::kDualInfeasible);
  const auto& u = unb.p.problem;
  EXPECT_NEAR(u.c.dot(unb.r.x), -1.0, 1e-8);
  EXPECT_LT((u.G * unb.r.x + unb.r.s).norm(), 1e-8);
  EXPECT_GE(unb.r.s.minCoeff(), -1e-12);
}

TEST(CbfReader, MalformedFilesNameTheLine) {
  struct Case {
    std::string text, expect;
  } cases[] = {
      {"OBJSENSE\nMIN\n", "test.cbf:1: the file must start with VER"},
      {"VER\n4\nVAR\n2 1\nL+ 3\n", "test.cbf:5: VAR: cone dimensions exceed"},
      {"VER\n4\nVAR\n3 2\nL+ 1\nQ 1\n", "test.cbf:6: VAR: cone dimensions sum to 2"},
      {"VER\n4\nVAR\n3 1\nEXP 3\n", "test.cbf:5: cone 'EXP' is not supported"},
      {"VER\n4\nVAR\n1 1\nF 1\nOBJACOORD\n1\n3 1.0\n", "test.cbf:8: OBJACOORD variable index 3 is out of range"},
      {"VER\n4\nVAR\n1 1\nF 1\nOBJACOORD\n2\n0 1.0\n", "test.cbf:8: OBJACOORD: the file ends inside the block"},
      {"VER\n4\nVAR\n1 1\nF 1\nOBJACOORD\n1\n0 x\n", "test.cbf:8: OBJACOORD value: 'x' is not a finite number"},
      {"VER\n4\nVAR\n1 1\nF 1\nACOORD\n1\n0 0 1\n", "test.cbf:6: ACOORD must come after CON"},
      {"VER\n4\nVAR\n1 1\nF 1\nCON\n1 1\nL+ 1\nACOORD\n1\n0 0\n", "test.cbf:11: ACOORD: expected 3 entries"},
      {"VER\n4\nVAR\n1 1\nF 1\nINT\n1\n0\n", "test.cbf:6: INT: integer variables are not supported"},
      {"VER\n4\nPSDVAR\n1\n2\n", "test.cbf:3: PSDVAR: semidefinite"},
      {"VER\n4\nVAR\n1 1\nF 1\nFOO\n", "test.cbf:6: unknown keyword 'FOO'"},
      {"VER\n9\n", "test.cbf:2: VER version 9 is out of range"},
      {"VER\n4\nOBJSENSE\nUP\n", "test.cbf:4: OBJSENSE must be MIN or MAX"},
      {"VER\n4\nVAR\n2 1\nQR 1\n", "test.cbf:5: VAR cone QR dimension 1 is out of range"},
      {"VER\n4\n", "no VAR block"},
  };
  for (const auto& c : cases) {
    try {
      parse(c.text);
      ADD_FAILURE() << "accepted:\n" << c.text;
    } catch (const bivo::Error& e) {
      EXPECT_NE(std::string(e.what()).find(c.expect), std::string::npos) << c.text << "\n" << e.what();
    }
  }
}

TEST(CbfReader, ExtensionDecidesTheFormat) {
  EXPECT_TRUE(bivo::experiments::is_cbf_path("a/b.cbf"));
  EXPECT_TRUE(bivo::experiments::is_cbf_path("x.CBF"));
  EXPECT_FALSE(bivo::experiments::is_cbf_path("x.json"));
  EXPECT_FALSE(bivo::experiments::is_cbf_path("cbf"));
}

// Found by fuzzing (fuzz_cbf, tests/fuzz/regressions/cbf/): the VAR and CON headers alone used to
// decide allocations of O(n + m) (and n + m = 2^31 overflowed int). Now the declared sizes are
// checked in 64 bits against max_cbf_size() (bivo --max-conic-size) before anything exists.
TEST(CbfReader, Var1073741824AndCon1073741824AreRefusedBeforeAllocating) {
  const auto message = [](const std::string& text) {
    try {
      parse(text);
    } catch (const bivo::Error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(message("VER\n4\nVAR\n1073741824 1\nF 1073741824\n"),
            "test.cbf:5: 1073741824 variables + 0 constraints exceed the limit of 16777216 (raise with "
            "--max-conic-size)");
  EXPECT_EQ(message("VER\n4\nVAR\n1 1\nF 1\nCON\n1073741824 1\nL+ 1073741824\n"),
            "test.cbf:8: 1 variables + 1073741824 constraints exceed the limit of 16777216 (raise with "
            "--max-conic-size)");
  // The limit counts n + m and can be raised (or lowered) by the caller.
  const std::int64_t saved = bivo::experiments::max_cbf_size();
  bivo::experiments::max_cbf_size() = 3;
  const std::string two_by_two = "VER\n4\nVAR\n2 1\nL+ 2\nCON\n2 1\nL+ 2\nACOORD\n1\n0 0 1\n";
  EXPECT_EQ(message(two_by_two),
            "test.cbf:8: 2 variables + 2 constraints exceed the limit of 3 (raise with --max-conic-size)");
  bivo::experiments::max_cbf_size() = 4;
  EXPECT_EQ(message(two_by_two), "accepted");
  bivo::experiments::max_cbf_size() = saved;
}

// Found by fuzz_cbf (tests/fuzz/regressions/cbf/line_of_form_feeds.cbf): a line of form feeds
// was not skipped as blank but had zero tokens, and the keyword was read from an empty list
// (UBSan: reference binding to null pointer). Every isspace-only line is blank now.
TEST(CbfReader, LineOfFormFeeds) {
  const CbfProblem p = parse("VER\n4\n\f\f\f\nVAR\n1 1\nF 1\n \t\v\r\nOBJACOORD\n1\n0 2\n");
  EXPECT_EQ(p.problem.num_variables(), 1);
  EXPECT_EQ(p.problem.c[0], 2.0);
  try {
    parse("\f\n");
    ADD_FAILURE() << "accepted a file of one blank line";
  } catch (const bivo::Error& e) {
    EXPECT_NE(std::string(e.what()).find("empty file: no VER"), std::string::npos) << e.what();
  }
}
