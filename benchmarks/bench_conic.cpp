// One epsilon-constraint step on image-like synthetic data in raw units (active
// constraint), per backend and size n (pixels). Counters: inner iterations of the backend.
// ipm-compressed is timed twice: with the thin QR of the n x 7 weighted [J r] blocks
// ("_with_qr") and on the formed 7x7 factors only; the IPM forms with and without the
// active-set Newton polish ("_NoPolish": the iterations alone). The table lives in docs/conic.md.
//
// BM_PaperSocp/<width>/<active>/<seed>: solve_conic on eq. `SOCP in our method` built from
// make_paper_step (raw units, t-distribution weights, 10 % invalid pixels kept as zero rows;
// the instances of the ECOS yardstick), from 40x30 to 640x480, constraint active (1) or
// inactive (0), seeds 1..3. Counters: interior-point iterations, the step's relative error
// against the exact QCQP step, whether the exit was a clean optimum, and the per-phase split
// of the last solve (ms). The step is IpmFullBackend's (SOCP built from the residuals, the
// compressed-form fallback when the full form's answer is not exact: counter "fallback").
// benchmarks/conic_vs_ecos.py runs them and prints the table.
#include <map>
#include <memory>
#include <string>

#include <benchmark/benchmark.h>

#include "solvers/step/exact_qcqp.h"
#include "solvers/step/ipm_compressed_backend.h"
#include "solvers/step/ipm_full_backend.h"
#include "solvers/step/ipopt_qcqp_backend.h"
#include "solvers/step/nlopt_slsqp_backend.h"
#include "solvers/step/qcqp_socp.h"
#include "tests/support/synthetic_qcqp.h"

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

struct PaperInstance {
  conic::SyntheticStep step;
  Eigen::VectorXd exact_step;
};

const PaperInstance& paper_instance(int width, bool active, int seed) {
  // One instance at a time: a 640x480 one holds ~100 MB.
  static std::string key;
  static std::unique_ptr<PaperInstance> slot;
  const std::string want = std::to_string(width) + "/" + std::to_string(active) + "/" + std::to_string(seed);
  if (!slot || key != want) {
    slot.reset();
    slot = std::make_unique<PaperInstance>();
    slot->step = conic::make_paper_step(width, width * 3 / 4, static_cast<std::uint32_t>(seed), active);
    slot->exact_step = solve_qcqp_exact(slot->step.lin.f1, slot->step.lin.f2, slot->step.epsilon).delta;
    key = want;
  }
  return *slot;
}

// The ipm-full step as the tracker takes it (IpmFullBackend's defaults: the paper's SOCP
// built from the residuals and solved in the backend's workspace, kept from step to step,
// and the compressed-form fallback when the full form's answer is not the exact step), so
// the time includes building the SOCP, which ECOS's does not.
void BM_PaperSocp(benchmark::State& state) {
  const int width = static_cast<int>(state.range(0));
  const PaperInstance& inst = paper_instance(width, state.range(1) != 0, static_cast<int>(state.range(2)));
  const Linearization& lin = inst.step.lin;
  const conic::IpmSettings settings = conic::step_ipm_settings();
  conic::QcqpConeStep r;
  conic::FullFormWorkspace workspace;  // as IpmFullBackend keeps one from step to step
  for (auto _ : state) {
    r = conic::with_compressed_fallback(
        conic::solve_qcqp_full(*lin.full1, *lin.full2, lin.f2, inst.step.epsilon, settings, workspace), lin.f1, lin.f2,
        inst.step.epsilon, settings);
    benchmark::DoNotOptimize(r.delta.data());
  }
  state.counters["n"] = width * (width * 3 / 4);
  state.counters["iterations"] = r.iterations;
  state.counters["step_error"] = (r.delta - inst.exact_step).norm() / std::max(1e-300, inst.exact_step.norm());
  state.counters["optimal"] = r.feasible && r.clean();
  state.counters["polished"] = r.polished;
  state.counters["fallback"] = r.fallback;
  for (int p = 0; p < static_cast<int>(conic::IpmPhase::kCount); ++p) {
    state.counters[std::string("ms_") + conic::to_string(static_cast<conic::IpmPhase>(p))] = 1e3 * r.timings.seconds[p];
  }
  state.counters["g_passes"] = r.timings.g_passes;
  state.SetLabel(r.status);
}

void paper_sizes(benchmark::internal::Benchmark* b) {
  for (int width : {40, 80, 160, 320, 640}) {
    for (int active : {1, 0}) {
      for (int seed : {1, 2, 3}) b->Args({width, active, seed});
    }
  }
}

}  // namespace

BENCHMARK(BM_PaperSocp)->Apply(paper_sizes)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Step_IpmFull)->Apply(all_sizes)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Step_IpmFull_NoPolish)->Apply(all_sizes)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Step_IpmCompressed_WithQr)->Apply(all_sizes)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Step_IpmCompressed_FactorsFormed)->Apply(all_sizes)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Step_IpmCompressed_FactorsFormed_NoPolish)->Apply(all_sizes)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Step_Exact)->Apply(all_sizes)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Step_Ipopt)->Apply(all_sizes)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Step_Nlopt)->Apply(all_sizes)->Unit(benchmark::kMicrosecond);
