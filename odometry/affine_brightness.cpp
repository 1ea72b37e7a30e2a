#include "odometry/affine_brightness.h"

#include <cmath>

#include <Eigen/Cholesky>

namespace bivo::odometry {

BrightnessCorrection solve_brightness(const BrightnessSums& s, bool radial, const RadialPrior& prior) {
  // In the kernels' centred x = I_1 - c: r ~ da x + e (+ dc q), then db = e - da c.
  BrightnessCorrection c;
  const double det = s.wxx * s.w - s.wx * s.wx;
  if (!(s.w > 0.0) || !(det > 1e-9 * s.wxx * s.w)) return c;
  Eigen::Vector3d beta(0.0, 0.0, 0.0);
  bool solved = false;
  // q separates from (x, 1) when its part orthogonal to them is more than round-off (q = 0 at
  // the identity: no motion, no fall-off to see); the ridge, when set, makes the fit well posed.
  const double q_orthogonal = s.wqq - (s.w * s.wxq * s.wxq - 2.0 * s.wx * s.wxq * s.wq + s.wxx * s.wq * s.wq) / det;
  if (radial && (q_orthogonal > 1e-8 * s.wxx || prior.strength > 0.0)) {
    const double ridge = prior.strength * s.w;
    Eigen::Matrix3d A;
    A << s.wxx, s.wx, s.wxq, s.wx, s.w, s.wq, s.wxq, s.wq, s.wqq + ridge;
    const Eigen::Vector3d b(s.wxr, s.wr, s.wqr - ridge * prior.current);
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(A);
    if (ldlt.info() == Eigen::Success) {
      beta = ldlt.solve(b);
      solved = beta.allFinite();
    }
  }
  if (!solved) {
    beta.z() = 0.0;
    beta.x() = (s.w * s.wxr - s.wx * s.wr) / det;
    beta.y() = (s.wxx * s.wr - s.wx * s.wxr) / det;
  }
  c.gain = beta.x();
  c.offset = beta.y() - c.gain * kBrightnessCentre;
  c.radial = beta.z();
  c.valid = true;
  return c;
}

BrightnessCorrection refit_stored_brightness(const KernelTable& kernels, const BrightnessFit& fit,
                                             const RadialPrior& prior, double gain, const TermBuffers& buf,
                                             std::size_t terms, int threads, double& sum_squares) {
  BrightnessCorrection c =
      solve_brightness(sum_over_chunks<BrightnessSums>(
                           terms, kChunkTerms, threads,
                           [&](std::size_t b, std::size_t e) { return kernels.brightness_sums(fit, buf, b, e); }),
                       fit.radial, prior);
  if (!(gain + c.gain >= kMinBrightnessGain)) c.valid = false;
  if (!c.valid) return c;
  struct SquareSum {
    double value = 0.0;
    void add(const SquareSum& other) { value += other.value; }
  };
  const BrightnessStep step{static_cast<float>(c.gain), static_cast<float>(c.offset), static_cast<float>(c.radial)};
  sum_squares = sum_over_chunks<SquareSum>(terms, kChunkTerms, threads, [&](std::size_t b, std::size_t e) {
                  return SquareSum{kernels.correct_brightness(fit, step, buf, b, e)};
                }).value;
  return c;
}

PooledFloats squared_radii(const KernelTable& kernels, const ReferenceArrays& ref, std::size_t padded) {
  PooledFloats rho2(padded);
  kernels.squared_radii(ref, rho2.data(), 0, ref.count);
  rho2.fill_from(ref.count, 0.0f);
  return rho2;
}

}  // namespace bivo::odometry
