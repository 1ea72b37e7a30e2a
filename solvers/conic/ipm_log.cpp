// The IPM in words: its log (ipm_log.h) and its exit (ipm_solver.h).
#include "solvers/conic/ipm_log.h"

#include <cstdio>
#include <string>

#include "solvers/conic/ipm_solver.h"

namespace bivo::solvers::conic {

std::string to_string(IpmStatus status) {
  switch (status) {
    case IpmStatus::kOptimal:
      return "optimal";
    case IpmStatus::kPrimalInfeasible:
      return "primal infeasible";
    case IpmStatus::kDualInfeasible:
      return "dual infeasible";
    case IpmStatus::kMaxIterations:
      return "max iterations";
    case IpmStatus::kNumericalTrouble:
      return "numerical trouble";
  }
  return "unknown";
}

std::string status_text(const IpmResult& r) {
  std::string s = to_string(r.status);
  if (r.reduced_accuracy) s += " (reduced accuracy" + (r.note.empty() ? std::string() : ": " + r.note) + ")";
  return s;
}

void log_ipm_header(std::ostream& log, int n, int p, int m, const ConeSpec& cones, int reduced_size,
                    long factor_nonzeros) {
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "conic IPM: n = %d, p = %d, m = %d (orthant %d, %zu SOC), reduced KKT %d x %d, L nnz %ld\n", n, p, m,
                cones.nonnegative, cones.soc.size(), reduced_size, reduced_size, factor_nonzeros);
  log << buf;
  log << "iter      pcost        dcost       gap     pres     dres     k/t       mu     step   sigma  ref\n";
}

void log_ipm_iteration(std::ostream& log, int k, const Residuals& r, double kt, double mu, double step, double sigma,
                       int refinement) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "%3d %+.5e %+.5e %8.1e %8.1e %8.1e %8.1e %8.1e %7.4f %7.4f %3d\n", k,
                r.primal_objective, r.dual_objective, r.gap, r.primal_residual, r.dual_residual, kt, mu, step, sigma,
                refinement);
  log << buf;
}

}  // namespace bivo::solvers::conic
