// The reference terms of a level (reference_terms.h): every instruction set's row kernel
// and the reference gradients against a per-pixel oracle written here from the formulas,
// bit for bit, on a level whose depth has holes, NaN and values outside [min, max], and
// whose width is not a multiple of the sixteen lanes.
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "odometry/kernels/rgbd_kernels.h"
#include "odometry/reference_terms.h"
#include "odometry/rgbd_pyramid.h"

using namespace bivo::odometry;

namespace {

constexpr double kMinDepth = 0.4, kMaxDepth = 6.0;

RgbdLevel ragged_level() {
  RgbdLevel level;
  const int w = 53, h = 40;  // 53 = 3 x 16 + 5
  level.K.fx = 517.3 / 2;
  level.K.fy = 516.5 / 2;
  level.K.cx = 318.6 / 2;
  level.K.cy = 255.3 / 2;
  for (ImageF* im : {&level.intensity, &level.depth}) {
    im->width = w;
    im->height = h;
    im->data.assign(static_cast<std::size_t>(w) * h, 0.0f);
  }
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      level.intensity.at(x, y) = static_cast<float>((x * 37 + y * 11) % 251) + 0.25f;
      float z = 0.3f + 0.11f * static_cast<float>((x * 7 + y * 13) % 61);  // 0.3 .. 6.9 m
      const int k = (x * 5 + y * 3) % 17;
      if (k == 0) z = 0.0f;  // missing
      if (k == 1) z = std::numeric_limits<float>::quiet_NaN();
      if (y == 7) z = 0.0f;  // a row with no term at all
      level.depth.at(x, y) = z;
    }
  }
  return level;
}

// The reference gradient's formula at one pixel along (du, dv) = (1, 0) or (0, 1): central
// difference, one-sided at the image's ends; with skip_missing (depth) only neighbours > 0
// count, and 0 when neither has one.
float oracle_derivative(const ImageF& im, int u, int v, int du, int dv, bool skip_missing) {
  const int u0 = u - du, v0 = v - dv, u1 = u + du, v1 = v + dv;
  const bool before = u0 >= 0 && v0 >= 0 && (!skip_missing || im.at(u0, v0) > 0.0f);
  const bool after = u1 < im.width && v1 < im.height && (!skip_missing || im.at(u1, v1) > 0.0f);
  if (before && after) return 0.5f * (im.at(u1, v1) - im.at(u0, v0));
  if (after) return im.at(u1, v1) - im.at(u, v);
  if (before) return im.at(u, v) - im.at(u0, v0);
  return 0.0f;
}

}  // namespace

TEST(ReferenceTerms, EveryKernelWritesTheTermsOfThePerPixelFormula) {
  const RgbdLevel level = ragged_level();
  const ImageF& D = level.depth;
  // The oracle: row-major, depth in [min, max], back-projected in double.
  std::vector<float> x, y, z, intensity, gi_u, gi_v, gd_u, gd_v;
  const float fx = static_cast<float>(level.K.fx), fy = static_cast<float>(level.K.fy);
  for (int v = 0; v < D.height; ++v) {
    for (int u = 0; u < D.width; ++u) {
      const double d = D.at(u, v);
      if (!(d >= kMinDepth && d <= kMaxDepth)) continue;
      x.push_back(static_cast<float>((u - level.K.cx) * (1.0 / level.K.fx) * d));
      y.push_back(static_cast<float>((v - level.K.cy) * (1.0 / level.K.fy) * d));
      z.push_back(D.at(u, v));
      intensity.push_back(level.intensity.at(u, v));
      gi_u.push_back(fx * oracle_derivative(level.intensity, u, v, 1, 0, false));
      gi_v.push_back(fy * oracle_derivative(level.intensity, u, v, 0, 1, false));
      gd_u.push_back(fx * oracle_derivative(D, u, v, 1, 0, true));
      gd_v.push_back(fy * oracle_derivative(D, u, v, 0, 1, true));
    }
  }
  ASSERT_GT(x.size(), 500u);
  ASSERT_LT(x.size(), D.data.size() * 3 / 4);  // holes and out-of-range depths are dropped
  const auto floats = [](const PooledFloats& v, std::size_t n) { return std::vector<float>(v.data(), v.data() + n); };
  for (const KernelIsa isa : {KernelIsa::kScalar, KernelIsa::kAvx2, KernelIsa::kAvx512Vl, KernelIsa::kAvx512}) {
    if (!kernels_available(isa)) continue;
    for (int threads : {1, 2}) {
      SCOPED_TRACE(std::string(to_string(isa)) + ", threads " + std::to_string(threads));
      const ReferenceTerms t = make_reference_terms(level, kMinDepth, kMaxDepth, false, threads, kernels(isa));
      ASSERT_EQ(t.count, x.size());
      EXPECT_EQ(floats(t.x, t.count), x);
      EXPECT_EQ(floats(t.y, t.count), y);
      EXPECT_EQ(floats(t.z, t.count), z);
      EXPECT_EQ(floats(t.intensity, t.count), intensity);
      ASSERT_EQ(t.x.size(), padded_terms(t.count));
      for (std::size_t k = t.count; k < t.x.size(); ++k) EXPECT_EQ(t.z[k], 0.0f);  // padding
      // With gradients: the same terms, and gradients of the terms in the same order.
      const ReferenceTerms g = make_reference_terms(level, kMinDepth, kMaxDepth, true, threads, kernels(isa));
      ASSERT_EQ(g.count, x.size());
      EXPECT_EQ(floats(g.x, g.count), x);
      EXPECT_EQ(floats(g.gi_u, g.count), gi_u);
      EXPECT_EQ(floats(g.gi_v, g.count), gi_v);
      EXPECT_EQ(floats(g.gd_u, g.count), gd_u);
      EXPECT_EQ(floats(g.gd_v, g.count), gd_v);
    }
  }
}

// The gradient of a term is that of its own pixel: on an intensity ramp I = 3 u + 2 v, the
// central differences are exact (fx dI/du = 3 fx, fy dI/dv = 2 fy) away from the borders.
TEST(ReferenceTerms, GradientsBelongToTheirTerms) {
  RgbdLevel level = ragged_level();
  for (int v = 0; v < level.depth.height; ++v) {
    for (int u = 0; u < level.depth.width; ++u) level.intensity.at(u, v) = static_cast<float>(3 * u + 2 * v);
  }
  const ReferenceTerms t = make_reference_terms(level, kMinDepth, kMaxDepth, true, 1);
  int interior = 0;
  for (std::size_t k = 0; k < t.count; ++k) {
    // Recover the pixel from the back-projection.
    const double u = t.x[k] / t.z[k] * level.K.fx + level.K.cx, v = t.y[k] / t.z[k] * level.K.fy + level.K.cy;
    const long pu = std::lround(u), pv = std::lround(v);
    if (pu <= 0 || pv <= 0 || pu >= level.depth.width - 1 || pv >= level.depth.height - 1) continue;
    ++interior;
    EXPECT_FLOAT_EQ(t.gi_u[k], static_cast<float>(3.0 * level.K.fx));
    EXPECT_FLOAT_EQ(t.gi_v[k], static_cast<float>(2.0 * level.K.fy));
  }
  EXPECT_GT(interior, 300);
}

// Split over threads, the rows' terms are counted in float before they are written. A depth
// counts when min <= double(z) <= max (reference_row's test): the float neighbours of bounds
// that float rounds up (0.4), down (0.7) or holds exactly (6.0) must fall on the same side
// of the bound as in that test, or the chunks' first indices shift.
TEST(ReferenceTerms, ThreadsCountTheDepthsAtTheBoundsAsTheRowTest) {
  RgbdLevel level = ragged_level();
  const auto around = [](double bound, int step) {
    float f = static_cast<float>(bound);
    for (; step < 0; ++step) f = std::nextafter(f, 0.0f);
    for (; step > 0; --step) f = std::nextafter(f, std::numeric_limits<float>::infinity());
    return f;
  };
  // A bound of inf (--max-depth inf) keeps infinite depths, as the row test does.
  const double inf = std::numeric_limits<double>::infinity();
  for (const auto& [min_depth, max_depth] : {std::pair{0.4, 6.0}, std::pair{0.7, 5.3}, std::pair{0.4, inf}}) {
    for (int v = 20; v < level.depth.height; ++v) {  // the lower half: the second thread's rows
      for (int u = 0; u < level.depth.width; ++u) {
        const double bound = (u + v) % 2 ? min_depth : max_depth;
        level.depth.at(u, v) =
            std::isinf(bound) ? (u % 3 ? 7.5f : static_cast<float>(inf)) : around(bound, (u + 3 * v) % 5 - 2);
      }
    }
    std::vector<float> z;  // the oracle: reference_row's test, pixel by pixel
    for (float d : level.depth.data) {
      if (double(d) >= min_depth && double(d) <= max_depth) z.push_back(d);
    }
    for (const KernelIsa isa : {KernelIsa::kScalar, KernelIsa::kAvx512}) {
      if (!kernels_available(isa)) continue;
      SCOPED_TRACE(std::string(to_string(isa)) + ", bounds " + std::to_string(min_depth));
      const ReferenceTerms t = make_reference_terms(level, min_depth, max_depth, false, 2, kernels(isa));
      ASSERT_EQ(t.count, z.size());
      EXPECT_EQ(std::vector<float>(t.z.data(), t.z.data() + t.count), z);
    }
  }
}
