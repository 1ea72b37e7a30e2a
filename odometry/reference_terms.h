#pragma once
// What one frame pair's problem needs at one level that does not depend on the pose,
// computed once per level (docs/odometry.md "Speed"):
//   * the terms: every reference pixel with depth in [min, max], back-projected
//     p = z K^-1 [x; 1], with its intensity I_1(x), as structure-of-arrays floats padded to
//     a multiple of kLaneGroup (padding: p = 0, flags stay 0 so it never counts);
//   * optionally the reference-side gradients fx dI_1/du, fy dI_1/dv, fx dD_1/du, fy dD_1/dv at
//     x (central differences; one-sided next to missing depth) for the inverse-compositional
//     and ESM Jacobians;
//   * the current level's intensity and depth interleaved as [I, D] per pixel, so that one
//     interpolation cell is two 16-byte reads.
// The arrays take their memory from the per-thread pool of pooled_floats.h: the terms of the
// next pair at the same level reuse these pages.
#include <cstddef>
#include <vector>

#include "odometry/kernels/kernels.h"
#include "odometry/rgbd_pyramid.h"

namespace bivo::odometry {

struct ReferenceTerms {
  PooledFloats x, y, z, intensity;
  PooledFloats gi_u, gi_v, gd_u, gd_v;  // empty unless asked for
  std::size_t count = 0;                // terms; the arrays hold padded_terms(count)

  ReferenceArrays view() const;
};

// Rows are split over `threads` threads (oneTBB, parallel_chunks.h); each row's terms come
// from the kernels' reference_row. The terms and their order depend on neither.
ReferenceTerms make_reference_terms(const RgbdLevel& reference, double min_depth, double max_depth, bool with_gradients,
                                    int threads = 1, const KernelTable& kernels = default_kernels());

// [I(0), D(0), I(1), D(1), ...] in row-major pixel order.
std::vector<float> interleave_intensity_depth(const RgbdLevel& level);

}  // namespace bivo::odometry
