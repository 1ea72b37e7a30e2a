#include "solvers/conic/dense_kernels.h"

#include <Eigen/Core>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define BIVO_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define BIVO_CLONES
#endif

namespace bivo::solvers::conic::kernels {

BIVO_CLONES void axpy(long n, double a, const double* x, double* y) {
  for (long i = 0; i < n; ++i) y[i] += a * x[i];
}

BIVO_CLONES void scaled_copy(long n, double a, const double* x, double* y) {
  for (long i = 0; i < n; ++i) y[i] = a * x[i];
}

BIVO_CLONES double dot(long n, const double* x, const double* y) {
  double s[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  long i = 0;
  for (; i + 8 <= n; i += 8) {
    for (int k = 0; k < 8; ++k) s[k] += x[i + k] * y[i + k];
  }
  double tail = 0.0;
  for (; i < n; ++i) tail += x[i] * y[i];
  return ((s[0] + s[4]) + (s[1] + s[5])) + ((s[2] + s[6]) + (s[3] + s[7])) + tail;
}

double max_abs(long n, const double* x) {
  // Eigen's packet max (a max reduction does not auto-vectorize without -ffast-math).
  return n > 0 ? Eigen::Map<const Eigen::VectorXd>(x, n).cwiseAbs().maxCoeff() : 0.0;
}

// x - x is 0 for finite x and NaN for +-inf and NaN; the sum is NaN iff one of them is.
BIVO_CLONES bool all_finite(long n, const double* x) {
  double s[4] = {0, 0, 0, 0};
  long i = 0;
  for (; i + 4 <= n; i += 4) {
    for (int k = 0; k < 4; ++k) s[k] += x[i + k] - x[i + k];
  }
  for (; i < n; ++i) s[0] += x[i] - x[i];
  const double t = (s[0] + s[1]) + (s[2] + s[3]);
  return t == 0.0;
}

}  // namespace bivo::solvers::conic::kernels
