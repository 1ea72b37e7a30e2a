// The per-iteration cost of the bi-objective layer's 6-variable steps (odometry size):
// the Gauss-Newton solve of eq. `linear system` and the exact QCQP step of eq. `QCQP`
// (active constraint: Newton on mu; inactive: one solve). Models are odometry-like:
// intensity terms ~1e4 times larger than depth terms.
#include <random>

#include <benchmark/benchmark.h>

#include "solvers/scalarization.h"
#include "solvers/step/exact_qcqp.h"
#include "solvers/step/gauss_newton.h"

namespace {

using bivo::solvers::QuadraticModel;

QuadraticModel random_model(int rows, double scale, std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::MatrixXd J(rows, 6);
  Eigen::VectorXd r(rows);
  for (int i = 0; i < rows; ++i) {
    for (int j = 0; j < 6; ++j) J(i, j) = scale * g(rng);
    r(i) = scale * g(rng);
  }
  QuadraticModel m;
  m.a = r.squaredNorm();
  m.b = J.transpose() * r;
  m.H = J.transpose() * J;
  return m;
}

bivo::solvers::Linearization odometry_like_linearization() {
  std::mt19937_64 rng(2026);
  bivo::solvers::Linearization lin;
  lin.f1 = random_model(200, 30.0, rng);
  lin.f2 = random_model(200, 0.05, rng);
  return lin;
}

// epsilon at a fraction of the way from min m2 to m2 at the m1-minimizer (0: tightest).
double epsilon_at(const bivo::solvers::Linearization& lin, double fraction) {
  const Eigen::VectorXd d1 = lin.f1.H.ldlt().solve(-lin.f1.b);
  const Eigen::VectorXd d2 = lin.f2.H.ldlt().solve(-lin.f2.b);
  const double lo = lin.f2.value(d2), hi = lin.f2.value(d1);
  return lo + fraction * (hi - lo);
}

void BM_GaussNewtonStep6(benchmark::State& state) {
  const auto lin = odometry_like_linearization();
  const auto sp = bivo::solvers::WeightedSum(1e4).make_subproblem(lin);
  bivo::solvers::GaussNewtonBackend gn;
  for (auto _ : state) benchmark::DoNotOptimize(gn.solve(sp).delta.data());
}
BENCHMARK(BM_GaussNewtonStep6);

void BM_ExactQcqpStep6(benchmark::State& state) {
  const auto lin = odometry_like_linearization();
  const double fraction = state.range(0) / 100.0;
  const double eps = epsilon_at(lin, fraction);
  const auto sp = bivo::solvers::EpsilonConstraint(eps).make_subproblem(lin);
  bivo::solvers::ExactQcqpBackend exact;
  int iterations = 0;
  for (auto _ : state) {
    const auto step = exact.solve(sp);
    iterations = step.iterations;
    benchmark::DoNotOptimize(step.delta.data());
  }
  state.counters["d_of_mu_evaluations"] = iterations;
}
// 10%, 50% of the range: active constraint; 150%: inactive (mu = 0).
BENCHMARK(BM_ExactQcqpStep6)->Arg(10)->Arg(50)->Arg(150);

}  // namespace
