#include "solvers/summary.h"

#include <cstdio>
#include <sstream>

namespace bivo::solvers {

const char* to_string(TerminationReason reason) {
  switch (reason) {
    case TerminationReason::kStepTolerance:
      return "step tolerance";
    case TerminationReason::kRelativeDecrease:
      return "relative decrease";
    case TerminationReason::kMaxIterations:
      return "iteration budget";
    case TerminationReason::kNoProgress:
      return "no progress";
    case TerminationReason::kNumericalFailure:
      return "numerical failure";
    case TerminationReason::kBackendFailure:
      return "backend failure";
    case TerminationReason::kDegeneratePoint:
      return "degenerate point";
  }
  return "unknown";
}

namespace {
std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}
}  // namespace

std::string Summary::BriefReport() const {
  std::ostringstream s;
  s << backend << ": " << scalarization << ", " << iterations << " iterations, F1 " << fmt("%.6e", initial_f1) << " -> "
    << fmt("%.6e", final_f1) << ", F2 " << fmt("%.6e", initial_f2) << " -> " << fmt("%.6e", final_f2) << ", "
    << (kind == ScalarizationKind::kWeightedSum ? "lambda " : "mu ") << fmt("%.6g", multiplier)
    << (feasible ? "" : ", INFEASIBLE") << ", " << to_string(termination) << ", " << fmt("%.3f", total_seconds * 1e3)
    << " ms";
  return s.str();
}

std::string Summary::FullReport() const {
  const bool ws = kind == ScalarizationKind::kWeightedSum;
  std::ostringstream s;
  s << "\nSolver Summary (bivo)\n\n";
  s << "Problem                   " << problem << "\n";
  s << "Scalarization             " << scalarization << "\n";
  s << "Backend                   " << backend << "\n\n";
  s << "                              Initial                    Final\n";
  s << "F1                   " << fmt("%24.12e", initial_f1) << " " << fmt("%24.12e", final_f1) << "\n";
  s << "F2                   " << fmt("%24.12e", initial_f2) << " " << fmt("%24.12e", final_f2) << "\n";
  if (!ws) s << "epsilon                                           " << fmt("%24.12e", epsilon) << "\n";
  s << (ws ? "lambda" : "mu    ") << "                                            " << fmt("%24.12e", multiplier)
    << "\n\n";
  s << " iter        F1            F2          " << (ws ? "lambda" : "  mu  ")
    << "       |step|     inner  acc feas   time(ms)\n";
  for (const auto& r : records) {
    char line[200];
    std::snprintf(line, sizeof line, "%5d %13.6e %13.6e %13.6e %11.3e%c %5d  %3s %4s %10.3f\n", r.iteration, r.f1, r.f2,
                  r.multiplier, r.step_norm, r.step_scale > 1.0 ? '*' : ' ', r.inner_iterations,
                  r.accepted ? "yes" : "no", r.feasible ? "yes" : "no", r.seconds * 1e3);
    s << line;
  }
  s << "\nTime (in seconds):\n";
  for (const auto& [phase, t] : phases.all()) {
    char line[120];
    std::snprintf(line, sizeof line, "  %-24s%12.6f\n", phase.c_str(), t);
    s << line;
  }
  s << fmt("  Total                   %12.6f\n", total_seconds);
  s << "\nIterations                " << iterations << "\n";
  if (extrapolated_steps + refused_extrapolations > 0) {
    s << "Extrapolated steps        " << extrapolated_steps << " (|step| marked *; " << refused_extrapolations
      << " refused)\n";
  }
  s << "Feasible                  " << (feasible ? "yes" : "no") << "\n";
  s << "Termination:              " << (converged() ? "CONVERGENCE" : "NO_CONVERGENCE") << " ("
    << to_string(termination) << (message.empty() ? "" : ": " + message) << ")\n";
  return s.str();
}

}  // namespace bivo::solvers
