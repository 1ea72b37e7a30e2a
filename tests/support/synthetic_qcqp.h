#pragma once
// Image-like synthetic epsilon-constraint steps in raw units (intensity 0..255, depth in
// metres), for the conic tests and benchmarks: pixels of a width x height grid, photometric
// rows J1 = grad I^T dpi/dP [I -P^x] with textured gradients (~30 gray/px), depth rows
// J2 = grad Z^T dpi/dP [I -P^x] - e_z^T [I -P^x]; invalid terms (no depth / out of view) are
// kept as zero rows (r = 0, J = 0, w = 0), as eq. `SOCP in our method` keeps them.
//   make_synthetic_step: n pixels of a 4:3 grid, ~5 % invalid, w1 = 1, w2 = 1/(0.01 Z)^2,
//     the constraint active at floor_2 + fraction * (m2(argmin m1) - floor_2).
//   make_paper_step: the instances of the paper's SOCP the benchmark and the ECOS yardstick
//     use: 10 % invalid, residuals with 5 % outliers, t-distribution weights (Kerl et al.
//     ICRA 2013, nu = 5, the scale re-estimated to its fixed point) on both objectives, and
//     the constraint active (fraction 0.3) or inactive (epsilon = 2 m2(argmin m1) - floor_2).
#include <cstdint>

#include "solvers/problem.h"

namespace bivo::solvers::conic {

struct SyntheticStep {
  Linearization lin;  // models and full residual data
  double epsilon = 0.0;
};

struct SyntheticStepOptions {
  int width = 0, height = 0;  // 0: a 4:3 grid of about n pixels (make_synthetic_step)
  double invalid_fraction = 0.05;
  bool t_weights = false;        // t-distribution weights and 5 % outliers (else w1 = 1, w2 = 1/sigma_Z^2)
  double active_fraction = 0.3;  // epsilon = floor_2 + fraction (m2(argmin m1) - floor_2); > 1: inactive
};

SyntheticStep make_synthetic_step(int n, std::uint32_t seed, double active_fraction = 0.3);
SyntheticStep make_synthetic_step(int n, std::uint32_t seed, const SyntheticStepOptions& options);
SyntheticStep make_paper_step(int width, int height, std::uint32_t seed, bool active);

}  // namespace bivo::solvers::conic
