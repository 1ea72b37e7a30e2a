// The public conic test suite (tests/conic_suite, docs/conic.md "The public test suite"): every
// problem of manifest.json read from its CBF file and solved by the IPM at its default settings
// and without the polish. Checked against the manifest, whose answers come from outside bivo
// (published optima, closed forms, planted solutions, or CVXOPT agreeing with bivo when the suite
// was generated):
//   * the status, on every well-posed problem (on an ill-posed one: never "optimal");
//   * the objective in the file's sense to 1e-7 relative, max(1, |expected|);
//   * the exit re-checked from the returned vectors on the unscaled data (conic_exit_check.h),
//     with rows the presolve removed as infinite bounds set aside as the solver certifies them.
#include <cmath>
#include <fstream>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "experiments/conic_files/cbf_file.h"
#include "solvers/conic/ipm_solver.h"
#include "tests/support/conic_exit_check.h"

using namespace bivo::solvers::conic;
using namespace bivo::solvers::conic::testing;

namespace {

const std::string kSuite = std::string(BIVO_TESTS_DIR) + "/conic_suite/";

struct Entry {
  std::string name, file, status;
  std::optional<double> objective;
  bool well_posed = true;
};

std::vector<Entry> manifest() {
  std::ifstream in(kSuite + "manifest.json");
  if (!in) return {{"missing_manifest", "", "", std::nullopt, true}};
  const nlohmann::json j = nlohmann::json::parse(in);
  std::vector<Entry> out;
  for (const auto& p : j.at("problems")) {
    Entry e{p.at("name"), p.at("file"), p.at("status"), std::nullopt, p.value("well_posed", true)};
    if (!p.at("objective").is_null()) e.objective = p.at("objective").get<double>();
    out.push_back(e);
  }
  return out;
}

// ctest lists each case by the problem's name, not its bytes.
void PrintTo(const Entry& e, std::ostream* os) { *os << e.name; }

IpmStatus expected_status(const std::string& s) {
  if (s == "optimal") return IpmStatus::kOptimal;
  if (s == "primal infeasible") return IpmStatus::kPrimalInfeasible;
  if (s == "dual infeasible") return IpmStatus::kDualInfeasible;
  ADD_FAILURE() << "manifest status '" << s << "'";
  return IpmStatus::kNumericalTrouble;
}

// The problem and the result without the rows the presolve treats as absent bounds (an orthant
// row with h >= infinity; a whole cone whose head is, its tail finite): the problem the solver
// solved and certified. Their z is 0 and s = h - G x, which a residual over ||h|| ~ 1e30 would
// only blur.
std::pair<ConicProblem, IpmResult> without_infinite_rows(const ConicProblem& p, const IpmResult& r, double infinity) {
  std::vector<int> keep;
  ConeSpec cones;
  for (int i = 0; i < p.cones.nonnegative; ++i) {
    if (p.h[i] < infinity) keep.push_back(i), ++cones.nonnegative;
  }
  int o = p.cones.nonnegative;
  for (const int d : p.cones.soc) {
    const bool tail_finite = (p.h.segment(o + 1, d - 1).array().abs() < infinity).all();
    if (!(p.h[o] >= infinity && tail_finite)) {
      for (int k = 0; k < d; ++k) keep.push_back(o + k);
      cones.soc.push_back(d);
    }
    o += d;
  }
  const Eigen::MatrixXd G = p.has_dense_G() ? p.dense_G : Eigen::MatrixXd(p.G);
  ConicProblem q = p;
  Eigen::MatrixXd Gk(keep.size(), G.cols());
  q.h.resize(keep.size());
  IpmResult s = r;
  s.z.resize(keep.size());
  s.s.resize(keep.size());
  for (std::size_t k = 0; k < keep.size(); ++k) {
    Gk.row(k) = G.row(keep[k]);
    q.h[k] = p.h[keep[k]];
    s.z[k] = r.z[keep[k]];
    s.s[k] = r.s[keep[k]];
  }
  q.dense_G.resize(0, 0);
  q.G = Gk.sparseView();
  q.cones = cones;
  return {q, s};
}

class ConicSuite : public ::testing::TestWithParam<std::tuple<Entry, bool>> {};

TEST_P(ConicSuite, StatusObjectiveAndCertificate) {
  const auto& [e, polish] = GetParam();
  ASSERT_NE(e.name, "missing_manifest") << "cannot read " << kSuite << "manifest.json";
  const bivo::experiments::CbfProblem cbf = bivo::experiments::read_cbf(kSuite + e.file);
  IpmSettings settings;
  settings.polish = polish;
  const IpmResult r = solve_conic(cbf.problem, settings);
  const std::string what = e.name + (polish ? "" : " --no-polish") + ": " + status_text(r);
  const IpmStatus want = expected_status(e.status);
  if (e.well_posed) {
    EXPECT_EQ(r.status, want) << what;
  } else {
    EXPECT_NE(r.status, IpmStatus::kOptimal) << what << " (no optimum exists)";
  }
  if (r.status == IpmStatus::kOptimal && want == IpmStatus::kOptimal && e.objective) {
    const double got = cbf.file_objective(r.primal_objective);
    EXPECT_LE(std::abs(got - *e.objective), 1e-7 * std::max(1.0, std::abs(*e.objective)))
        << what << ": objective " << got << ", expected " << *e.objective;
  }
  ExitTally tally;
  if (r.infinite_rows > 0) {
    const auto [q, s] = without_infinite_rows(cbf.problem, r, settings.infinity);
    EXPECT_EQ(q.h.size() + r.infinite_rows, cbf.problem.h.size()) << what;
    check_exit(q, s, what, tally);
  } else {
    check_exit(cbf.problem, r, what, tally);
  }
}

std::string test_name(const ::testing::TestParamInfo<std::tuple<Entry, bool>>& info) {
  return std::get<0>(info.param).name + (std::get<1>(info.param) ? "" : "_no_polish");
}

INSTANTIATE_TEST_SUITE_P(Public, ConicSuite, ::testing::Combine(::testing::ValuesIn(manifest()), ::testing::Bool()),
                         test_name);

}  // namespace
