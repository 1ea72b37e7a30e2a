// The frame statistics of a prepared frame (prepare_frame): summed block by block while the
// pyramid reduces level 0 into level 1, they must be the numbers of a separate pass over
// level 0 (frame_statistics) bit for bit, and those of the per-quantity functions
// (complexity_metric, variance: other summation orders) to rounding.
#include <algorithm>
#include <cmath>
#include <mutex>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "odometry/image_statistics.h"
#include "odometry/io/camera_intrinsics.h"
#include "odometry/rgbd_pyramid.h"
#include "odometry/tracker.h"

using namespace bivo::odometry;

namespace {

// 70x67: an odd height (its last row is reduced into no level-1 row) and a width that is no
// multiple of the eight lanes; holes in the depth.
io::RgbdImage ragged_image() {
  io::RgbdImage im;
  im.width = 70;
  im.height = 67;
  for (int y = 0; y < im.height; ++y) {
    for (int x = 0; x < im.width; ++x) {
      im.intensity.push_back(static_cast<float>(128.0 + 90.0 * std::sin(0.21 * x + 0.13 * y * y)));
      const bool hole = (x * 7 + y * 3) % 11 == 0;
      im.depth.push_back(hole ? 0.0f : static_cast<float>(1.5 + 0.4 * std::cos(0.05 * x * y)));
    }
  }
  return im;
}

double relative(double got, double want) { return std::abs(got - want) / std::abs(want); }

}  // namespace

TEST(FrameStatisticsTest, APreparedFrameHasTheNumbersOfASeparatePass) {
  const io::RgbdImage im = ragged_image();
  const io::Intrinsics K{60.0, 60.0, 34.5, 33.0};
  const double holes = static_cast<double>(std::count(im.depth.begin(), im.depth.end(), 0.0f));
  ASSERT_GT(holes, 300);
  for (int levels : {1, 3}) {
    for (int threads : {1, 2}) {
      for (int finest : {0, 1}) {
        if (finest >= levels) continue;
        SCOPED_TRACE("levels " + std::to_string(levels) + ", threads " + std::to_string(threads) + ", finest " +
                     std::to_string(finest));
        const PreparedFrame f = prepare_frame(im, K, levels, threads, finest);
        ASSERT_TRUE(f.has_statistics);
        const RgbdLevel& level0 = f.pyramid.levels[0];
        const FrameStatistics s = frame_statistics(level0);
        EXPECT_EQ(f.statistics.pi_intensity, s.pi_intensity);
        EXPECT_EQ(f.statistics.pi_depth, s.pi_depth);
        EXPECT_EQ(f.statistics.var_intensity, s.var_intensity);
        EXPECT_EQ(f.statistics.var_depth, s.var_depth);
        EXPECT_EQ(f.statistics.valid_depth_fraction, s.valid_depth_fraction);
        EXPECT_LT(relative(s.pi_intensity, complexity_metric(level0.intensity, false)), 1e-6);
        EXPECT_LT(relative(s.pi_depth, complexity_metric(level0.depth, true)), 1e-6);
        EXPECT_LT(relative(s.var_intensity, variance(level0.intensity, false)), 1e-6);
        EXPECT_LT(relative(s.var_depth, variance(level0.depth, true)), 1e-6);
        EXPECT_EQ(s.valid_depth_fraction, (70.0 * 67.0 - holes) / (70.0 * 67.0));
      }
    }
  }
}

// The pyramid reports the level-0 rows it reduced into level 1, in blocks that tile them once
// (rows 0-65 of 67: the last row has no level-1 row), on whatever thread reduced them.
TEST(FrameStatisticsTest, ThePyramidReportsEveryReducedRowOnce) {
  for (int threads : {1, 2}) {
    std::mutex m;
    std::vector<std::pair<int, int>> blocks;
    const RgbdPyramid p = build_pyramid(ragged_image(), io::Intrinsics{60.0, 60.0, 34.5, 33.0}, 3, threads, 0,
                                        [&](const RgbdLevel& level0, int first, int last) {
                                          EXPECT_EQ(level0.level, 0);
                                          EXPECT_EQ(level0.intensity.height, 67);
                                          std::lock_guard<std::mutex> lock(m);
                                          blocks.emplace_back(first, last);
                                        });
    std::sort(blocks.begin(), blocks.end());
    int next = 0;
    for (const auto& [first, last] : blocks) {
      EXPECT_EQ(first, next);
      EXPECT_GT(last, first);
      next = last;
    }
    EXPECT_EQ(next, 66);
    EXPECT_EQ(p.levels[1].intensity.height, 33);
  }
}
