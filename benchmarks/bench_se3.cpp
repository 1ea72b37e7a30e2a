#include <benchmark/benchmark.h>

#include "solvers/geometry/se3.h"

static void BM_Se3ExpLog(benchmark::State& state) {
  bivo::solvers::se3::Vector6d xi;
  xi << 0.1, -0.2, 0.3, 0.01, 0.02, -0.03;
  for (auto _ : state) {
    auto T = bivo::solvers::se3::exp(xi);
    benchmark::DoNotOptimize(bivo::solvers::se3::log(T));
  }
}
BENCHMARK(BM_Se3ExpLog);
