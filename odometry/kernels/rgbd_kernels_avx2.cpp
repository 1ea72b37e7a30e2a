// The per-pixel kernels with eight float lanes (AVX2 + FMA). CMake compiles this file with
// -mavx2 -mfma when BIVO_AVX2 is on; the dispatcher (rgbd_kernels.cpp) uses it only on a
// CPU that reports both.
#define BIVO_KERNEL_NS avx2_kernels
#include "odometry/kernels/rgbd_kernels_impl.h"

#if !defined(__AVX2__) || !defined(__FMA__)
#error "rgbd_kernels_avx2.cpp must be compiled with -mavx2 -mfma"
#endif

namespace bivo::odometry {

const KernelTable& avx2_kernel_table() {
  static const KernelTable table = avx2_kernels::make_table<avx2_kernels::Avx2Lanes>(KernelIsa::kAvx2);
  return table;
}

}  // namespace bivo::odometry
