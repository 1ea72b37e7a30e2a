#pragma once
// Image-like synthetic epsilon-constraint steps in raw units (intensity 0..255, depth in
// metres), for the conic tests and benchmarks: n pixels of a 4:3 grid, photometric rows
// J1 = grad I^T dpi/dP [I -P^x] with textured gradients (~30 gray/px), depth rows
// J2 = grad Z^T dpi/dP [I -P^x] - e_z^T [I -P^x], weights w1 = 1 and w2 = 1/(0.01 Z)^2,
// ~5% invalid terms (r = 0, J = 0, w = 0). epsilon is placed so the constraint is active:
// floor_2 + fraction * (m2(argmin m1) - floor_2).
#include <cstdint>

#include "solvers/problem.h"

namespace bivo::solvers::conic {

struct SyntheticStep {
  Linearization lin;  // models and full residual data
  double epsilon = 0.0;
};

SyntheticStep make_synthetic_step(int n, std::uint32_t seed, double active_fraction = 0.3);

}  // namespace bivo::solvers::conic
