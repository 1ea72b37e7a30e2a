#include "odometry/affine_brightness.h"

namespace bivo::odometry {

BrightnessCorrection solve_brightness(const BrightnessSums& s) {
  // In the kernels' centred x = I_1 - c: r ~ da x + e, then db = e - da c.
  const double det = s.wxx * s.w - s.wx * s.wx;
  BrightnessCorrection c;
  if (!(s.w > 0.0) || !(det > 1e-9 * s.wxx * s.w)) return c;
  c.gain = (s.w * s.wxr - s.wx * s.wr) / det;
  c.offset = (s.wxx * s.wr - s.wx * s.wxr) / det - c.gain * kBrightnessCentre;
  c.valid = true;
  return c;
}

BrightnessCorrection refit_stored_brightness(const KernelTable& kernels, const float* intensity, const TermBuffers& buf,
                                             std::size_t terms, bool weighted, int threads, double& sum_squares) {
  const BrightnessCorrection c =
      solve_brightness(sum_over_chunks<BrightnessSums>(terms, kChunkTerms, threads, [&](std::size_t b, std::size_t e) {
        return kernels.brightness_sums(intensity, buf, weighted, b, e);
      }));
  if (!c.valid) return c;
  struct SquareSum {
    double value = 0.0;
    void add(const SquareSum& other) { value += other.value; }
  };
  const float g = static_cast<float>(c.gain), o = static_cast<float>(c.offset);
  sum_squares = sum_over_chunks<SquareSum>(terms, kChunkTerms, threads, [&](std::size_t b, std::size_t e) {
                  return SquareSum{kernels.correct_brightness(g, o, intensity, buf, b, e)};
                }).value;
  return c;
}

}  // namespace bivo::odometry
