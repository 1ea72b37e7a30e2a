// frame_statistics() (one pass over both images, eight float lanes per sum, a scalar tail per
// row) against the separate double-precision functions that define each number.
#include <random>

#include <gtest/gtest.h>

#include "odometry/image_statistics.h"

using namespace bivo::odometry;

namespace {

// Widths that leave every part of a row's loops some work: whole groups of eight and single
// pixels after them (53 = 6 x 8 + 5, 61 = 7 x 8 + 5), and the full 640.
RgbdLevel random_level(int width, int height, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> gray(0.0f, 255.0f), depth(0.5f, 4.0f), u(0.0f, 1.0f);
  RgbdLevel L;
  L.intensity = ImageF{width, height, {}};
  L.depth = ImageF{width, height, {}};
  for (int k = 0; k < width * height; ++k) {
    L.intensity.data.push_back(gray(rng));
    L.depth.data.push_back(u(rng) < 0.2f ? 0.0f : depth(rng));  // a fifth missing
  }
  return L;
}

}  // namespace

TEST(ImageStatistics, OnePassEqualsTheDefinitionsForEveryRowLength) {
  for (const int width : {53, 61, 640}) {
    SCOPED_TRACE(width);
    const RgbdLevel L = random_level(width, 37, static_cast<unsigned>(width));
    const FrameStatistics s = frame_statistics(L);
    EXPECT_NEAR(s.pi_intensity, complexity_metric(L.intensity, false), 1e-6 * s.pi_intensity);
    EXPECT_NEAR(s.pi_depth, complexity_metric(L.depth, true), 1e-6 * s.pi_depth);
    EXPECT_NEAR(s.var_intensity, variance(L.intensity, false), 1e-5 * s.var_intensity);
    EXPECT_NEAR(s.var_depth, variance(L.depth, true), 1e-5 * s.var_depth);
    std::size_t valid = 0;
    for (float d : L.depth.data) valid += d > 0.0f;
    EXPECT_DOUBLE_EQ(s.valid_depth_fraction, double(valid) / L.depth.data.size());
    // Row chunks on two threads: the same sums in the same order.
    const FrameStatistics two = frame_statistics(L, 2);
    EXPECT_EQ(two.pi_intensity, s.pi_intensity);
    EXPECT_EQ(two.pi_depth, s.pi_depth);
    EXPECT_EQ(two.var_intensity, s.var_intensity);
    EXPECT_EQ(two.var_depth, s.var_depth);
  }
}
