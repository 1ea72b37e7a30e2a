#include "solvers/conic/ipm_timings.h"

#include <cstdio>

namespace bivo::solvers::conic {

const char* to_string(IpmPhase phase) {
  switch (phase) {
    case IpmPhase::kValidation:
      return "validation";
    case IpmPhase::kEquilibration:
      return "equilibration";
    case IpmPhase::kKktSetup:
      return "kkt_setup";
    case IpmPhase::kOrdering:
      return "ordering";
    case IpmPhase::kSymbolic:
      return "symbolic";
    case IpmPhase::kResiduals:
      return "residuals";
    case IpmPhase::kGPasses:
      return "g_passes";
    case IpmPhase::kKktFactor:
      return "kkt_factor";
    case IpmPhase::kKktSolve:
      return "kkt_solve";
    case IpmPhase::kRefinement:
      return "refinement";
    case IpmPhase::kCones:
      return "cones";
    case IpmPhase::kPolish:
      return "polish";
    case IpmPhase::kOther:
      return "other";
    case IpmPhase::kCount:
      break;
  }
  return "unknown";
}

void record_phases(const IpmTimings& t, PhaseProfile* profile) {
  if (!profile) return;
  for (int p = 0; p < static_cast<int>(IpmPhase::kCount); ++p) {
    if (t.seconds[p] > 0.0)
      profile->add(std::string("subproblem/ipm_") + to_string(static_cast<IpmPhase>(p)), t.seconds[p]);
  }
}

IpmTimings& IpmTimings::operator+=(const IpmTimings& o) {
  for (int p = 0; p < static_cast<int>(IpmPhase::kCount); ++p) seconds[p] += o.seconds[p];
  g_passes += o.g_passes;
  kkt_factors += o.kkt_factors;
  kkt_solves += o.kkt_solves;
  refinement_steps += o.refinement_steps;
  polish_attempts += o.polish_attempts;
  kkt_setups += o.kkt_setups;
  ipm_operations += o.ipm_operations;
  polish_operations += o.polish_operations;
  return *this;
}

double IpmTimings::setup_seconds() const {
  double s = 0.0;
  for (int p = static_cast<int>(IpmPhase::kValidation); p <= static_cast<int>(IpmPhase::kSymbolic); ++p)
    s += seconds[p];
  return s;
}

double IpmTimings::iteration_seconds() const {
  double s = 0.0;
  for (int p = static_cast<int>(IpmPhase::kResiduals); p <= static_cast<int>(IpmPhase::kOther); ++p) {
    if (p != static_cast<int>(IpmPhase::kPolish)) s += seconds[p];
  }
  return s;
}

double IpmTimings::total_seconds() const {
  double s = 0.0;
  for (double v : seconds) s += v;
  return s;
}

std::string IpmTimings::text(int iterations) const {
  std::string out;
  char buf[160];
  const double total = total_seconds();
  auto share = [&](double s) { return total > 0.0 ? 100.0 * s / total : 0.0; };
  std::snprintf(buf, sizeof buf, "time by phase (ms, share of %.3f ms):\n", 1e3 * total);
  out += buf;
  auto line = [&](const char* name, double s) {
    std::snprintf(buf, sizeof buf, "  %-14s %10.4f  %5.1f %%\n", name, 1e3 * s, share(s));
    out += buf;
  };
  std::snprintf(buf, sizeof buf, " set-up %.4f ms:\n", 1e3 * setup_seconds());
  out += buf;
  for (int p = static_cast<int>(IpmPhase::kValidation); p <= static_cast<int>(IpmPhase::kSymbolic); ++p) {
    line(to_string(static_cast<IpmPhase>(p)), seconds[p]);
  }
  std::snprintf(buf, sizeof buf, " iterations %.4f ms (%d iterations, %.4f ms each):\n", 1e3 * iteration_seconds(),
                iterations, iterations > 0 ? 1e3 * iteration_seconds() / iterations : 0.0);
  out += buf;
  for (int p = static_cast<int>(IpmPhase::kResiduals); p <= static_cast<int>(IpmPhase::kOther); ++p) {
    if (p != static_cast<int>(IpmPhase::kPolish)) line(to_string(static_cast<IpmPhase>(p)), seconds[p]);
  }
  std::snprintf(buf, sizeof buf, " polish (%d attempts, %.3g operations against the method's %.3g):\n", polish_attempts,
                polish_operations, ipm_operations);
  out += buf;
  line("polish", (*this)[IpmPhase::kPolish]);
  std::snprintf(buf, sizeof buf, " counts: %d G passes, %d KKT factorizations, %d KKT solves, %d refinement steps\n",
                g_passes, kkt_factors, kkt_solves, refinement_steps);
  out += buf;
  return out;
}

}  // namespace bivo::solvers::conic
