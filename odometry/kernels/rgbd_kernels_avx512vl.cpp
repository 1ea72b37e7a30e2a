// The AVX2 kernels (eight float lanes, Avx2Lanes) built once more with AVX-512VL. Its EVEX
// encoding gives the same 256-bit operations 32 vector registers instead of 16, so the warp
// and the normal equations spill far less of the pose and their constants to the stack (the
// warp's vector reloads from the stack: 45 -> 19 instructions; its level-0 pass 6-7 % faster
// on an AVX-512 Xeon; docs/odometry.md "Speed"). The
// operations and their order are those of rgbd_kernels_avx2.cpp: results are bit-identical
// (tests/test_odometry_kernels.cpp). CMake compiles this file with -mavx2 -mfma -mavx512f
// -mavx512vl when BIVO_AVX512VL is on; the dispatcher uses it only on a CPU that reports all four.
#define BIVO_KERNEL_NS avx512vl_kernels
#include "odometry/kernels/rgbd_kernels_impl.h"

#if !defined(__AVX2__) || !defined(__FMA__) || !defined(__AVX512VL__)
#error "rgbd_kernels_avx512vl.cpp must be compiled with -mavx2 -mfma -mavx512f -mavx512vl"
#endif

namespace bivo::odometry {

const KernelTable& avx512vl_kernel_table() {
  static const KernelTable table = avx512vl_kernels::make_table<avx512vl_kernels::Avx2Lanes>(KernelIsa::kAvx512Vl);
  return table;
}

}  // namespace bivo::odometry
