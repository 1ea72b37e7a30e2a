// `bivo conic FILE` end to end: a known LP/SOCP solved from JSON (dense rows and
// triplets), and bad input rejected with a message naming the file and the fault.
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

namespace {

struct CliRun {
  int code;
  std::string out;
};

CliRun run(const std::string& args) {
  const std::string cmd = std::string(BIVO_BINARY) + " conic " + args + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  std::string out;
  char buf[512];
  while (p && fgets(buf, sizeof buf, p)) out += buf;
  const int status = p ? pclose(p) : -1;
  return {WEXITSTATUS(status), out};
}

std::string write(const std::string& name, const std::string& text) {
  const std::string path = testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

double objective(const std::string& out) {
  const auto k = out.find("objective: ");
  return k == std::string::npos ? std::nan("") : std::stod(out.substr(k + 11));
}

}  // namespace

TEST(ConicCli, SolvesDenseAndTripletFormats) {
  // min -x1 - x2 s.t. x1 + 2 x2 <= 4, 3 x1 + x2 <= 6, x >= 0: optimum -2.8.
  const std::string dense =
      write("lp_dense.json",
            R"({"c": [-1, -1], "G": [[1, 2], [3, 1], [-1, 0], [0, -1]], "h": [4, 6, 0, 0], "cones": {"l": 4}})");
  CliRun r = run(dense + " --verbose");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("status: optimal"), std::string::npos) << r.out;
  EXPECT_NEAR(objective(r.out), -2.8, 1e-7) << r.out;
  EXPECT_NE(r.out.find("pcost"), std::string::npos) << r.out;
  // min t s.t. ||(x1 - 3, x2 - 4)|| <= t: distance 0 at (3, 4); plus x1 + x2 = 1 -> 6/sqrt(2).
  const std::string soc = write("soc_triplets.json",
                                R"({"c": [1, 0, 0], "A": [[0, 1, 1]], "b": [1],
          "G": {"rows": 3, "cols": 3, "triplets": [[0, 0, -1], [1, 1, -1], [2, 2, -1]]},
          "h": [0, -3, -4], "cones": {"q": [3]}})");
  r = run(soc);
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NEAR(objective(r.out), 6.0 / std::sqrt(2.0), 1e-12) << r.out;  // polished: to rounding
  EXPECT_NE(r.out.find("then polished"), std::string::npos) << r.out;
  r = run(soc + " --no-polish");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NEAR(objective(r.out), 6.0 / std::sqrt(2.0), 1e-7) << r.out;
  EXPECT_EQ(r.out.find("polished"), std::string::npos) << r.out;
}

TEST(ConicCli, BadInputIsAnErrorNamingTheFault) {
  struct Case {
    std::string json, expect;
  } cases[] = {
      {R"({"c": [1], "G": [[1]], "h": [1], "cones": {"l": 2}})", "sum to 2"},
      {R"({"c": [1, 2], "G": [[1]], "h": [1], "cones": {"l": 1}})", "row 0 must have 2"},
      {R"({"c": [1], "G": [[1]], "h": ["x"], "cones": {"l": 1}})", "h[0] is not a number"},
      {R"({"c": [1], "G": [[1]], "h": [1]})", "missing \"cones\""},
      {R"({"c": [1], "G": {"rows": 1, "cols": 1, "triplets": [[3, 0, 1]]}, "h": [1], "cones": {"l": 1}})", "outside"},
      {R"({"c": [1], "G": [[1]], "h": [1], "cones": {"q": [0]}})", "cones.q[0]"},
      {R"({"c": [1], "G": [[1]], "h": [1, 2], "cones": {"l": 2}})", "G has 1 rows but h has 2"},
      // A row count h does not have is refused before a matrix of that many rows is built.
      {R"({"c": [1], "G": {"rows": 2147481824, "cols": 1, "triplets": []}, "h": [], "cones": {}})",
       "G has 2147481824 rows but h has 0 entries"},
      {R"({"c": [1], "A": {"rows": 3, "cols": 1, "triplets": []}, "b": [1], "G": [[1]], "h": [1], "cones": {"l": 1}})",
       "A has 3 rows but b has 1 entries"},
      {R"({"c": [1], )", "not valid JSON"},
  };
  int k = 0;
  for (const auto& c : cases) {
    const std::string path = write("bad" + std::to_string(k++) + ".json", c.json);
    const CliRun r = run(path);
    EXPECT_EQ(r.code, 1) << c.json << "\n" << r.out;
    EXPECT_NE(r.out.find(c.expect), std::string::npos) << c.json << "\n" << r.out;
    EXPECT_NE(r.out.find(path), std::string::npos) << r.out;
  }
  const CliRun missing = run("/nonexistent/problem.json");
  EXPECT_EQ(missing.code, 1);
  EXPECT_NE(missing.out.find("cannot open"), std::string::npos) << missing.out;
}

TEST(ConicCli, ReadsCbfAndPrintsThePhaseSplit) {
  // CBF (by extension): max x0 + x1 s.t. x0 - x1 = 0, x0 + x1 - 2 <= 0, plus the constant 1: 3.
  const std::string cbf =
      write("lp.cbf",
            "VER\n4\nOBJSENSE\nMAX\nVAR\n2 1\nF 2\nCON\n2 2\nL= 1\nL- 1\nOBJACOORD\n2\n0 1\n1 1\nOBJBCOORD\n1\n"
            "ACOORD\n4\n0 0 1\n0 1 -1\n1 0 1\n1 1 1\nBCOORD\n1\n1 -2\n");
  CliRun r = run(cbf + " --verbose");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("status: optimal"), std::string::npos) << r.out;
  const auto k = r.out.find("file objective (max, constant included): ");
  ASSERT_NE(k, std::string::npos) << r.out;
  EXPECT_NEAR(std::stod(r.out.substr(k + 41)), 3.0, 1e-8) << r.out;
  for (const char* phase : {"time by phase", "equilibration", "ordering", "symbolic", "g_passes", "kkt_factor",
                            "kkt_solve", "refinement", "cones", "polish"}) {
    EXPECT_NE(r.out.find(phase), std::string::npos) << phase << "\n" << r.out;
  }
  // --format cbf on another extension; a malformed file names file and line, exit 1.
  const std::string bad = write("bad_cbf.txt", "VER\n4\nVAR\n1 1\nEXP 1\n");
  r = run(bad + " --format cbf");
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find(bad + ":5: cone 'EXP' is not supported"), std::string::npos) << r.out;
}
