// The public conic suite (tests/conic_suite, docs/conic.md "The public test suite"), one case per
// problem: BM_ConicSuite/<name> solves it with the IPM's defaults, BM_ConicSuite_NoPolish/<name>
// without the polish. The CBF file is read once, outside the timing; each iteration is a whole
// solve_conic call (validation, equilibration, KKT set-up, iterations, polish), as a user makes
// it. Counters: iterations, whether the exit is the manifest's status ("right"), the objective's
// relative error against the manifest, whether the answer is the polished point, the polish's
// time over the rest of the solve's (polish_share), its attempts, both times per solve
// (polish_ns, rest_ns) and the operation counts the polish's budget compares (polish_ops, ipm_ops).
// benchmarks/conic_suite_vs_cvxopt.py runs them next to CVXOPT and prints the table.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>

#include <benchmark/benchmark.h>
#include <nlohmann/json.hpp>

#include "experiments/conic_files/cbf_file.h"
#include "solvers/conic/ipm_solver.h"

namespace {

using namespace bivo::solvers::conic;

struct SuiteCase {
  std::string name, status;
  bool has_objective = false;
  double objective = 0.0;
  std::shared_ptr<bivo::experiments::CbfProblem> cbf;
};

bool right_status(const IpmResult& r, const std::string& want) {
  return (want == "optimal" && r.status == IpmStatus::kOptimal) ||
         (want == "primal infeasible" && r.status == IpmStatus::kPrimalInfeasible) ||
         (want == "dual infeasible" && r.status == IpmStatus::kDualInfeasible);
}

void solve_case(benchmark::State& state, const SuiteCase& c, bool polish) {
  IpmSettings settings;
  settings.polish = polish;
  IpmResult r;
  double polish_seconds = 0.0, seconds = 0.0;
  for (auto _ : state) {
    r = solve_conic(c.cbf->problem, settings);
    benchmark::DoNotOptimize(r.x.data());
    polish_seconds += r.timings[IpmPhase::kPolish];
    seconds += r.seconds;
  }
  state.counters["iterations"] = r.iterations;
  // The polish's time over the rest of the solve (set-up and iterations), all runs together.
  state.counters["polish_share"] = seconds > polish_seconds ? polish_seconds / (seconds - polish_seconds) : 0.0;
  state.counters["polish_attempts"] = r.timings.polish_attempts;
  state.counters["polish_ns"] = 1e9 * polish_seconds / static_cast<double>(state.iterations());
  state.counters["rest_ns"] = 1e9 * (seconds - polish_seconds) / static_cast<double>(state.iterations());
  state.counters["polish_ops"] = r.timings.polish_operations;
  state.counters["ipm_ops"] = r.timings.ipm_operations;
  state.counters["right"] = right_status(r, c.status);
  state.counters["reduced_accuracy"] = r.reduced_accuracy;
  state.counters["polished"] = r.polished;
  if (c.has_objective && r.status == IpmStatus::kOptimal) {
    state.counters["objective_error"] =
        std::abs(c.cbf->file_objective(r.primal_objective) - c.objective) / std::max(1.0, std::abs(c.objective));
  }
  state.SetLabel(status_text(r));
}

// Registered at start-up from the manifest; a missing suite registers nothing.
const bool registered = [] {
  const std::string dir = BIVO_CONIC_SUITE_DIR;
  std::ifstream in(dir + "/manifest.json");
  if (!in) {
    std::fprintf(stderr, "no manifest at %s\n", dir.c_str());
    return false;
  }
  const nlohmann::json manifest = nlohmann::json::parse(in);
  for (const auto& p : manifest.at("problems")) {
    SuiteCase c;
    c.name = p.at("name");
    c.status = p.at("status");
    if (!p.at("objective").is_null()) c.has_objective = true, c.objective = p.at("objective").get<double>();
    c.cbf = std::make_shared<bivo::experiments::CbfProblem>(
        bivo::experiments::read_cbf(dir + "/" + p.at("file").get<std::string>()));
    for (const bool polish : {true, false}) {
      benchmark::RegisterBenchmark(((polish ? "BM_ConicSuite/" : "BM_ConicSuite_NoPolish/") + c.name).c_str(),
                                   [c, polish](benchmark::State& st) { solve_case(st, c, polish); })
          ->Unit(benchmark::kMicrosecond);
    }
  }
  return true;
}();

}  // namespace
