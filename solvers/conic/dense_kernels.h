#pragma once
// The few loops the IPM spends its time in on a dense G (the paper's SOCP: 2n+2 rows, 7
// columns): axpy and dot over long contiguous arrays. Compiled twice, for x86-64-v3 (AVX2 +
// FMA) and for the baseline, and picked once at load time by the CPU (GCC/Clang
// target_clones), so one binary runs on every x86-64 machine and uses 4-wide FMA where it
// can. Elsewhere they are plain loops.
namespace bivo::solvers::conic::kernels {

void axpy(long n, double a, const double* x, double* y);         // y += a x
void scaled_copy(long n, double a, const double* x, double* y);  // y = a x
double dot(long n, const double* x, const double* y);            // 8 partial sums
double max_abs(long n, const double* x);                         // 0 for n = 0
bool all_finite(long n, const double* x);

}  // namespace bivo::solvers::conic::kernels
