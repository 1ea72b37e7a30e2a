// The per-pixel kernels with sixteen float lanes (Avx512Lanes, AVX-512F). The source is that
// of the eight-lane kernels; only the lane type differs, so the lane sums hold other subsets of
// the terms and results agree with kAvx2 to float rounding (tests/test_odometry_kernels.cpp).
// CMake compiles this file with -mavx2 -mfma -mavx512f when BIVO_AVX512 is on; the dispatcher
// uses it only on a CPU that reports AVX-512F.
#define BIVO_KERNEL_NS avx512_kernels
#include "odometry/kernels/rgbd_kernels_impl.h"

#if !defined(__AVX512F__)
#error "rgbd_kernels_avx512.cpp must be compiled with -mavx2 -mfma -mavx512f"
#endif

namespace bivo::odometry {

const KernelTable& avx512_kernel_table() {
  static const KernelTable table = avx512_kernels::make_table<avx512_kernels::Avx512Lanes>(KernelIsa::kAvx512);
  return table;
}

}  // namespace bivo::odometry
