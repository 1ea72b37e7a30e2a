// One epsilon-constraint step on image-like synthetic data in raw units (active
// constraint), per backend and size n (pixels). Counters: inner iterations of the backend.
// ipm-compressed is timed twice: with the thin QR of the n x 7 weighted [J r] blocks
// ("_with_qr") and on the formed 7x7 factors only; the IPM forms with and without the
// active-set Newton polish ("_NoPolish": the iterations alone). The table lives in docs/conic.md.
#include <map>
#include <memory>

#include <benchmark/benchmark.h>

#include "solvers/conic/qcqp_socp.h"
#include "solvers/conic/synthetic_qcqp.h"
#include "solvers/step/exact_qcqp.h"
#include "solvers/step/ipm_compressed_backend.h"
#include "solvers/step/ipm_full_backend.h"
#include "solvers/step/ipopt_qcqp_backend.h"
#include "solvers/step/nlopt_slsqp_backend.h"

namespace {

using namespace bivo::solvers;

const conic::SyntheticStep& step_data(int n) {
  static std::map<int, std::unique_ptr<conic::SyntheticStep>> cache;
  auto& slot = cache[n];
  if (!slot) slot = std::make_unique<conic::SyntheticStep>(conic::make_synthetic_step(n, 1, 0.35));
  return *slot;
}

Subproblem subproblem(const conic::SyntheticStep& s, const Linearization& lin) {
  Subproblem sp;
  sp.kind = ScalarizationKind::kEpsilonConstraint;
  sp.lin = &lin;
  sp.epsilon = s.epsilon;
  return sp;
}

template <class Backend, class... Args>
void run_backend(benchmark::State& state, bool models_only, Args... args) {
  const conic::SyntheticStep& s = step_data(static_cast<int>(state.range(0)));
  Linearization lin = s.lin;
  if (models_only) {
    lin.full1.reset();
    lin.full2.reset();
  }
  Backend backend(args...);
  int iterations = 0;
  bool ok = true;
  for (auto _ : state) {
    const StepResult r = backend.solve(subproblem(s, lin));
    iterations = r.iterations;
    ok = ok && r.feasible && r.delta.allFinite();
    benchmark::DoNotOptimize(r.delta.data());
  }
  state.counters["iterations"] = iterations;
  if (!ok) state.SkipWithError("step failed");
}

void BM_Step_IpmFull(benchmark::State& st) { run_backend<IpmFullBackend>(st, false); }
void BM_Step_IpmFull_NoPolish(benchmark::State& st) {
  run_backend<IpmFullBackend>(st, false, conic::unpolished_step_ipm_settings());
}
void BM_Step_IpmCompressed_WithQr(benchmark::State& st) { run_backend<IpmCompressedBackend>(st, false); }
void BM_Step_Ipopt(benchmark::State& st) { run_backend<IpoptQcqpBackend>(st, true); }
void BM_Step_Nlopt(benchmark::State& st) { run_backend<NloptSlsqpBackend>(st, true); }
void BM_Step_Exact(benchmark::State& st) { run_backend<ExactQcqpBackend>(st, true); }

// ipm-compressed once the 7x7 factors are formed: the IPM on two cones of dimension 7.
void compressed_factors_formed(benchmark::State& state, const conic::IpmSettings& settings) {
  const conic::SyntheticStep& s = step_data(static_cast<int>(state.range(0)));
  const conic::ConeFactor f1 = conic::factor_from_residuals(*s.lin.full1);
  const conic::ConeFactor f2 = conic::factor_from_residuals(*s.lin.full2);
  int iterations = 0;
  for (auto _ : state) {
    const conic::QcqpConeStep r = conic::solve_qcqp_compressed(f1, f2, s.lin.f2, s.epsilon, settings);
    iterations = r.iterations;
    benchmark::DoNotOptimize(r.delta.data());
  }
  state.counters["iterations"] = iterations;
}
void BM_Step_IpmCompressed_FactorsFormed(benchmark::State& st) {
  compressed_factors_formed(st, conic::step_ipm_settings());
}
void BM_Step_IpmCompressed_FactorsFormed_NoPolish(benchmark::State& st) {
  compressed_factors_formed(st, conic::unpolished_step_ipm_settings());
}

void all_sizes(benchmark::internal::Benchmark* b) {
  for (int n : {1200, 4800, 19200, 76800, 307200}) b->Arg(n);
}

}  // namespace

BENCHMARK(BM_Step_IpmFull)->Apply(all_sizes)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Step_IpmFull_NoPolish)->Apply(all_sizes)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Step_IpmCompressed_WithQr)->Apply(all_sizes)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Step_IpmCompressed_FactorsFormed)->Apply(all_sizes)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Step_IpmCompressed_FactorsFormed_NoPolish)->Apply(all_sizes)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Step_Exact)->Apply(all_sizes)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Step_Ipopt)->Apply(all_sizes)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Step_Nlopt)->Apply(all_sizes)->Unit(benchmark::kMicrosecond);
