// The per-pixel kernels with one float lane (the fallback of every build, and the reference
// of the AVX2 agreement tests).
#define BIVO_KERNEL_NS scalar_kernels
#include "odometry/kernels/rgbd_kernels_impl.h"

namespace bivo::odometry {

const KernelTable& scalar_kernel_table() {
  static const KernelTable table = scalar_kernels::make_table<scalar_kernels::ScalarLanes>(KernelIsa::kScalar);
  return table;
}

}  // namespace bivo::odometry
