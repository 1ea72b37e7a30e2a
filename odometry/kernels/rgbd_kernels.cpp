// Choice of the kernels' instruction set, and the sums' reductions.
#include "odometry/kernels/rgbd_kernels.h"

#include <string>

#include "solvers/error.h"

namespace bivo::odometry {

const KernelTable& scalar_kernel_table();
#ifdef BIVO_HAVE_AVX2_KERNELS
const KernelTable& avx2_kernel_table();
#endif
#ifdef BIVO_HAVE_AVX512VL_KERNELS
const KernelTable& avx512vl_kernel_table();
#endif
#ifdef BIVO_HAVE_AVX512_KERNELS
const KernelTable& avx512_kernel_table();
#endif

const char* to_string(KernelIsa isa) {
  switch (isa) {
    case KernelIsa::kScalar:
      return "scalar";
    case KernelIsa::kAvx2:
      return "avx2";
    case KernelIsa::kAvx512Vl:
      return "avx512vl";
    case KernelIsa::kAvx512:
      return "avx512";
  }
  return "?";
}

bool kernels_available(KernelIsa isa) {
  switch (isa) {
    case KernelIsa::kScalar:
      return true;
    case KernelIsa::kAvx2: {
#ifdef BIVO_HAVE_AVX2_KERNELS
      static const bool cpu = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
      return cpu;
#else
      return false;
#endif
    }
    case KernelIsa::kAvx512Vl: {
#ifdef BIVO_HAVE_AVX512VL_KERNELS
      static const bool cpu = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
                              __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl");
      return cpu;
#else
      return false;
#endif
    }
    case KernelIsa::kAvx512: {
#ifdef BIVO_HAVE_AVX512_KERNELS
      static const bool cpu = __builtin_cpu_supports("avx512f");
      return cpu;
#else
      return false;
#endif
    }
  }
  return false;
}

const KernelTable& kernels(KernelIsa isa) {
  if (!kernels_available(isa)) {
    throw Error(std::string("per-pixel kernels for ") + to_string(isa) +
                " are not available (not built in, or this CPU lacks the instructions)");
  }
#ifdef BIVO_HAVE_AVX512_KERNELS
  if (isa == KernelIsa::kAvx512) return avx512_kernel_table();
#endif
#ifdef BIVO_HAVE_AVX512VL_KERNELS
  if (isa == KernelIsa::kAvx512Vl) return avx512vl_kernel_table();
#endif
#ifdef BIVO_HAVE_AVX2_KERNELS
  if (isa == KernelIsa::kAvx2) return avx2_kernel_table();
#endif
  return scalar_kernel_table();
}

const KernelTable& default_kernels() {
  static const KernelTable& table = kernels(kernels_available(KernelIsa::kAvx512)     ? KernelIsa::kAvx512
                                            : kernels_available(KernelIsa::kAvx512Vl) ? KernelIsa::kAvx512Vl
                                            : kernels_available(KernelIsa::kAvx2)     ? KernelIsa::kAvx2
                                                                                      : KernelIsa::kScalar);
  return table;
}

void WarpSums::add(const WarpSums& o) {
  f_i += o.f_i;
  f_d += o.f_d;
  ss_i += o.ss_i;
  ss_d += o.ss_d;
  valid_i += o.valid_i;
  valid_d += o.valid_d;
}

void GramSums::add(const GramSums& o) {
  for (int e = 0; e < 28; ++e) g[e] += o.g[e];
  weight_sum += o.weight_sum;
}

void NormalSums::add(const NormalSums& o) {
  intensity.add(o.intensity);
  depth.add(o.depth);
}

void ScaleSums::add(const ScaleSums& o) {
  sum += o.sum;
  slope += o.slope;
}

void BrightnessSums::add(const BrightnessSums& o) {
  w += o.w;
  wx += o.wx;
  wxx += o.wxx;
  wr += o.wr;
  wxr += o.wxr;
  wq += o.wq;
  wxq += o.wxq;
  wqq += o.wqq;
  wqr += o.wqr;
}

void JointScaleSums::add(const JointScaleSums& o) {
  m_ii += o.m_ii;
  m_id += o.m_id;
  m_dd += o.m_dd;
  t40 += o.t40;
  t31 += o.t31;
  t22 += o.t22;
  t13 += o.t13;
  t04 += o.t04;
  count += o.count;
}

void WeighSums::add(const WeighSums& o) {
  f_i += o.f_i;
  f_d += o.f_d;
  weight_sum_i += o.weight_sum_i;
  weight_sum_d += o.weight_sum_d;
}

}  // namespace bivo::odometry
