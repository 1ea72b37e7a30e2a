// The renderer's depth-noise shape and outlier defects (odometry/synth/defects.h) against
// closed forms on views whose true depth is known: a fronto-parallel plane (noise growing as
// z^p, a per-frame disparity offset, speckle matching failures) and a vertical step edge
// (flying pixels only in the occlusion band, between the two sides).
#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "odometry/synth/defects.h"
#include "odometry/synth/render.h"

namespace synth = bivo::odometry::synth;

namespace {

constexpr int W = 640, H = 480;

// A view whose true depth is z_left left of column `edge` and z_right from it on, seen head-on.
synth::SceneView step_view(double z_left, double z_right, int edge) {
  synth::SceneView v;
  v.width = W;
  v.height = H;
  v.true_depth.resize(static_cast<std::size_t>(W) * H);
  v.cos_incidence.assign(v.true_depth.size(), 1.0f);
  v.radiance.assign(v.true_depth.size(), Eigen::Vector3f(0.5f, 0.5f, 0.5f));
  for (int y = 0; y < H; ++y) {
    for (int u = 0; u < W; ++u) v.true_depth[static_cast<std::size_t>(y) * W + u] = u < edge ? z_left : z_right;
  }
  return v;
}

// Noise on, but nothing random unless a test switches it on: no depth noise, no quantization.
synth::RenderSettings quiet() {
  synth::RenderSettings r;
  r.depth.noise_coeff = 0.0;
  r.depth.disparity_step_px = 0.0;
  r.depth.noise_correlation_px = 0.0;
  r.depth.max_range_m = 8.0;
  return r;
}

double depth_m(const synth::RenderedFrame& f, std::size_t i) { return f.depth[i] / 5000.0; }

double fb(const synth::RenderSettings& r) { return r.depth.ir_focal_px * r.depth.baseline_m; }

}  // namespace

TEST(SynthDepthOutliers, NoiseSpreadGrowsAsDepthToTheExponent) {
  // Oracle: independent pixels of sigma c Z^p: the sample spread at Z = 3 over that at Z = 1 is 3^p.
  for (double p : {2.0, 3.0}) {
    synth::RenderSettings r = quiet();
    r.depth.noise_coeff = 1e-3;
    r.defects.noise_exponent = p;
    double spread[2];
    int k = 0;
    for (double Z : {1.0, 3.0}) {
      const synth::SceneView v = step_view(Z, Z, 0);
      const synth::RenderedFrame f = synth::sense(v, v, r, 0);
      double sum = 0, sum2 = 0;
      for (std::size_t i = 0; i < f.depth.size(); ++i) {
        const double e = depth_m(f, i) - Z;
        sum += e;
        sum2 += e * e;
      }
      const double n = static_cast<double>(f.depth.size());
      spread[k++] = std::sqrt(sum2 / n - (sum / n) * (sum / n));
      // 300k pixels: the sample spread is within 1 % of sigma; the 0.2 mm PNG step adds 0.06 mm RMS.
      EXPECT_NEAR(spread[k - 1], 1e-3 * std::pow(Z, p), 0.01 * 1e-3 * std::pow(Z, p) + 1e-4) << "p " << p;
    }
    EXPECT_NEAR(spread[1] / spread[0], std::pow(3.0, p), 0.05 * std::pow(3.0, p)) << "p " << p;
  }
}

TEST(SynthDepthOutliers, DisparityOffsetMovesTheWholePlaneByItsClosedForm) {
  // Oracle: every pixel of a plane at Z reads Z / (1 - Z o_k / fb), o_k the frame's offset, and
  // the offsets of many frames spread step / sqrt(1 - m^2) (the AR(1) walk's stationary spread).
  synth::RenderSettings r = quiet();
  r.sensor_noise = false;
  r.defects.disparity_offset_step_px = 0.05;
  r.defects.disparity_offset_memory = 0.6;
  const double Z = 2.5;
  const synth::SceneView v = step_view(Z, Z, 0);
  for (std::uint64_t k : {0u, 7u}) {
    const double o = synth::disparity_offset(r.defects, r.noise_seed, k);
    ASSERT_NE(o, 0.0);
    const synth::RenderedFrame f = synth::sense(v, v, r, k);
    const double expected = Z / (1 - Z * o / fb(r));
    for (std::size_t i : {std::size_t{0}, std::size_t{240 * W + 320}, f.depth.size() - 1})
      EXPECT_NEAR(depth_m(f, i), expected, 1.01e-4) << "frame " << k;
  }
  double sum2 = 0, lag1 = 0, prev = 0;
  const int frames = 2000;
  for (int k = 0; k < frames; ++k) {
    const double o = synth::disparity_offset(r.defects, r.noise_seed, static_cast<std::uint64_t>(k));
    sum2 += o * o;
    if (k > 0) lag1 += o * prev;
    prev = o;
  }
  const double sd = std::sqrt(sum2 / frames), stationary = 0.05 / std::sqrt(1 - 0.36);
  EXPECT_NEAR(sd, stationary, 0.15 * stationary);
  EXPECT_NEAR(lag1 / (frames - 1) / (sd * sd), 0.6, 0.1);  // the walk's lag-1 correlation is its memory
  r.defects.disparity_offset_step_px = 0.0;
  EXPECT_EQ(synth::disparity_offset(r.defects, r.noise_seed, 7), 0.0);
}

TEST(SynthDepthOutliers, SpeckleOutliersAreTheRequestedShareAndTwoToEightPixelsOff) {
  // Oracle: pixel i fails with probability s, independently: the count of pixels off the plane
  // is Binomial(n, s); each failure's disparity fb/z - fb/Z lies in +-[2, 8] px.
  synth::RenderSettings r = quiet();
  r.defects.speckle_outliers = 0.01;
  const double Z = 2.0;
  const synth::SceneView v = step_view(Z, Z, 0);
  for (std::uint64_t k : {0u, 1u}) {
    const synth::RenderedFrame f = synth::sense(v, v, r, k);
    std::size_t off = 0, near_side = 0;
    for (std::size_t i = 0; i < f.depth.size(); ++i) {
      ASSERT_GT(f.depth[i], 0);  // every failure at 2 m stays within 0.5-8 m
      const double z = depth_m(f, i);
      if (std::fabs(z - Z) < 1.01e-4) continue;
      ++off;
      near_side += z < Z;
      const double dd = std::fabs(fb(r) / z - fb(r) / Z);
      EXPECT_GE(dd, 2.0 - 0.01);
      EXPECT_LE(dd, 8.0 + 0.01);
    }
    const double n = static_cast<double>(f.depth.size()), sd = std::sqrt(n * 0.01 * 0.99);
    EXPECT_NEAR(static_cast<double>(off), 0.01 * n, 5 * sd) << "frame " << k;
    EXPECT_NEAR(static_cast<double>(near_side), 0.5 * off, 5 * std::sqrt(0.25 * off));  // either sign
  }
  r.defects.speckle_outliers = 0.0;
  const synth::RenderedFrame clean = synth::sense(v, v, r, 0);
  for (std::size_t i = 0; i < clean.depth.size(); i += 97) EXPECT_NEAR(depth_m(clean, i), Z, 1.01e-4);
}

TEST(SynthDepthOutliers, FlyingPixelsLieInTheOcclusionBandBetweenTheTwoSides) {
  // A step from 1 m to 2 m at column 320: the jump marks columns 319 and 320, the band (2 px)
  // drops 317-322. With share s, s of those 6 x 480 pixels come back: in 318-321 at a depth
  // between 1 and 2 m; every other pixel keeps its own side's depth.
  synth::RenderSettings r = quiet();
  r.sensor_noise = false;
  const synth::SceneView v = step_view(1.0, 2.0, 320);
  const synth::RenderedFrame none = synth::sense(v, v, r, 0);
  for (int u = 317; u <= 322; ++u) EXPECT_EQ(none.depth[240 * W + u], 0) << "column " << u;
  r.defects.flying_pixels = 0.5;
  for (std::uint64_t k : {0u, 3u}) {
    const synth::RenderedFrame f = synth::sense(v, v, r, k);
    std::size_t kept = 0, inner = 0, between = 0;
    for (int y = 0; y < H; ++y) {
      for (int u = 0; u < W; ++u) {
        const std::size_t i = static_cast<std::size_t>(y) * W + u;
        const double z = depth_m(f, i);
        if (u < 317 || u > 322) {
          ASSERT_NEAR(z, u < 320 ? 1.0 : 2.0, 1.01e-4) << u << "," << y;
          continue;
        }
        if (f.depth[i] == 0) continue;
        ++kept;
        if (u == 317 || u == 322) {
          // 3 px from the other side: no band neighbour differs, the pixel keeps its own depth.
          EXPECT_NEAR(z, u < 320 ? 1.0 : 2.0, 1.01e-4);
          continue;
        }
        ++inner;
        EXPECT_GE(z, 1.0 - 1e-4);
        EXPECT_LE(z, 2.0 + 1e-4);
        between += z > 1.01 && z < 1.99;
      }
    }
    const double n = 6.0 * H, sd = std::sqrt(n * 0.25);
    EXPECT_NEAR(static_cast<double>(kept), 0.5 * n, 5 * sd) << "frame " << k;
    EXPECT_GT(between, inner * 9 / 10);  // t uniform in [0, 1): nearly all strictly between
  }
}
