#pragma once
// The IPM's per-iteration log (IpmSettings::log): a header with the sizes, one line per
// iteration.
#include <ostream>

#include "solvers/conic/cones.h"
#include "solvers/conic/residuals.h"

namespace bivo::solvers::conic {

void log_ipm_header(std::ostream& log, int n, int p, int m, const ConeSpec& cones, int reduced_size,
                    long factor_nonzeros);
// kt = kappa / tau; refinement = the KKT solve's refinement steps.
void log_ipm_iteration(std::ostream& log, int k, const Residuals& r, double kt, double mu, double step, double sigma,
                       int refinement);

}  // namespace bivo::solvers::conic
