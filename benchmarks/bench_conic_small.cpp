// The conic IPM's fixed cost per solve on small problems, where it dominates: each case
// solves a fixed set of problems with solve_conic (no workspace: a fresh solve, as the CLI,
// Python and a test suite call it) and reports the time per solve ("s_per_solve").
//   BM_ConicSmall_Socp/<n>: 16 random feasible SOCPs with n variables, n orthant rows,
//     max(1, n/4) second-order cones of dimension 4 and n/4 equalities (half dense).
//   BM_ConicSmall_Lp/<n>: 16 random feasible LPs, n variables, 2n inequalities.
//   BM_ConicHuber/<polish>: the CVXOPT book's Huber fitting (tests/support/huber_fit.h), with
//     and without the active-set polish.
// Counters: interior-point iterations and polish attempts per solve, optimal exits (of 1).
#include <map>
#include <random>
#include <utility>
#include <vector>

#include <benchmark/benchmark.h>

#include "solvers/conic/ipm_solver.h"
#include "tests/support/huber_fit.h"
#include "tests/support/random_conic.h"

namespace {

using namespace bivo::solvers::conic;

// Feasible and bounded by construction: a strictly interior primal-dual point (x0, s0; y0, z0).
ConicProblem random_problem(const ConeSpec& spec, int n, int p, std::mt19937& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  const ConeProduct K(spec);
  ConicProblem prob;
  prob.cones = spec;
  prob.A = testing::random_sparse(p, n, 0.5, rng);
  prob.G = testing::random_sparse(K.dim(), n, 0.5, rng);
  Eigen::VectorXd x0(n), y0(p);
  for (int i = 0; i < n; ++i) x0[i] = g(rng);
  for (int i = 0; i < p; ++i) y0[i] = g(rng);
  const Eigen::VectorXd s0 = testing::random_interior(K, rng), z0 = testing::random_interior(K, rng);
  prob.b = prob.A * x0;
  prob.h = prob.G * x0 + s0;
  prob.c = -(prob.G.transpose() * z0 + prob.A.transpose() * y0);
  return prob;
}

std::vector<ConicProblem> socps(int n) {
  std::mt19937 rng(static_cast<unsigned>(n));
  ConeSpec spec;
  spec.nonnegative = n;
  spec.soc.assign(std::max(1, n / 4), 4);
  std::vector<ConicProblem> out;
  for (int i = 0; i < 16; ++i) out.push_back(random_problem(spec, n, n / 4, rng));
  return out;
}

std::vector<ConicProblem> lps(int n) {
  std::mt19937 rng(static_cast<unsigned>(1000 + n));
  ConeSpec spec;
  spec.nonnegative = 2 * n;
  std::vector<ConicProblem> out;
  for (int i = 0; i < 16; ++i) out.push_back(random_problem(spec, n, 0, rng));
  return out;
}

void solve_all(benchmark::State& state, const std::vector<ConicProblem>& problems, const IpmSettings& settings) {
  double iterations = 0.0, attempts = 0.0, optimal = 0.0;
  long solves = 0;
  for (auto _ : state) {
    for (const ConicProblem& p : problems) {
      const IpmResult r = solve_conic(p, settings);
      benchmark::DoNotOptimize(r.x.data());
      iterations += r.iterations;
      attempts += r.timings.polish_attempts;
      optimal += r.status == IpmStatus::kOptimal && !r.reduced_accuracy;
      ++solves;
    }
  }
  const double k = static_cast<double>(std::max(1L, solves));
  state.counters["iterations"] = iterations / k;
  state.counters["polish_attempts"] = attempts / k;
  state.counters["optimal"] = optimal / k;
  state.counters["s_per_solve"] =
      benchmark::Counter(static_cast<double>(problems.size()),
                         benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// Made once per size (a case runs several times: repetitions, the estimate of iterations).
const std::vector<ConicProblem>& cached(std::vector<ConicProblem> (*make)(int), int n) {
  static std::map<std::pair<std::vector<ConicProblem> (*)(int), int>, std::vector<ConicProblem>> cache;
  auto it = cache.find({make, n});
  if (it == cache.end()) it = cache.emplace(std::make_pair(make, n), make(n)).first;
  return it->second;
}

void BM_ConicSmall_Socp(benchmark::State& state) {
  solve_all(state, cached(socps, static_cast<int>(state.range(0))), IpmSettings{});
}

void BM_ConicSmall_Lp(benchmark::State& state) {
  solve_all(state, cached(lps, static_cast<int>(state.range(0))), IpmSettings{});
}

void BM_ConicHuber(benchmark::State& state) {
  static const std::vector<ConicProblem> problems{testing::huber_fit()};
  IpmSettings settings;
  settings.polish = state.range(0) != 0;
  solve_all(state, problems, settings);
}

}  // namespace

BENCHMARK(BM_ConicSmall_Socp)->Arg(4)->Arg(16)->Arg(48)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ConicSmall_Lp)->Arg(8)->Arg(32)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ConicHuber)->Arg(1)->Arg(0)->Unit(benchmark::kMicrosecond);
