#include "odometry/rgbd_pyramid.h"

#include <string>

#include "solvers/error.h"

namespace bivo::odometry {

namespace {

// Half resolution, each coarse pixel reduce(a, b, c, d) of its 2x2 fine block (row-major).
template <typename Reduce>
ImageF downsample(const ImageF& fine, Reduce reduce) {
  ImageF c;
  c.width = fine.width / 2;
  c.height = fine.height / 2;
  c.data.resize(static_cast<std::size_t>(c.width) * c.height);
  for (int y = 0; y < c.height; ++y) {
    const float* r0 = fine.data.data() + static_cast<std::size_t>(2 * y) * fine.width;
    const float* r1 = r0 + fine.width;
    float* out = c.data.data() + static_cast<std::size_t>(y) * c.width;
    for (int x = 0; x < c.width; ++x) out[x] = reduce(r0[2 * x], r0[2 * x + 1], r1[2 * x], r1[2 * x + 1]);
  }
  return c;
}

}  // namespace

ImageF downsample_intensity(const ImageF& fine) {
  return downsample(fine, [](float a, float b, float c, float d) { return 0.25f * (a + b + c + d); });
}

ImageF downsample_depth(const ImageF& fine) {
  // Mean of the valid (> 0) depths only: averaging in a hole would invent a depth.
  return downsample(fine, [](float a, float b, float c, float d) {
    float sum = 0.0f;
    int count = 0;
    for (float v : {a, b, c, d}) {
      if (v > 0.0f) {
        sum += v;
        ++count;
      }
    }
    return count > 0 ? sum / count : 0.0f;
  });
}

RgbdPyramid build_pyramid(const io::RgbdImage& image, const io::Intrinsics& K, int levels) {
  if (levels < 1) throw Error("pyramid needs at least 1 level, got " + std::to_string(levels));
  const int cw = image.width >> (levels - 1), ch = image.height >> (levels - 1);
  if (cw < 8 || ch < 8) {
    throw Error("pyramid of " + std::to_string(levels) + " levels on a " + std::to_string(image.width) + "x" +
                std::to_string(image.height) + " image leaves a " + std::to_string(cw) + "x" + std::to_string(ch) +
                " coarsest level (minimum 8x8)");
  }
  RgbdPyramid p;
  p.timestamp = image.timestamp;
  p.levels.resize(static_cast<std::size_t>(levels));
  RgbdLevel& base = p.levels[0];
  base.level = 0;
  base.K = K;
  base.intensity.width = base.depth.width = image.width;
  base.intensity.height = base.depth.height = image.height;
  base.intensity.data = image.intensity;
  base.depth.data = image.depth;
  for (int l = 1; l < levels; ++l) {
    RgbdLevel& L = p.levels[static_cast<std::size_t>(l)];
    L.level = l;
    L.K = K.at_level(l);
    L.intensity = downsample_intensity(p.levels[static_cast<std::size_t>(l - 1)].intensity);
    L.depth = downsample_depth(p.levels[static_cast<std::size_t>(l - 1)].depth);
  }
  return p;
}

void central_gradients(const ImageF& image, ImageF& gx, ImageF& gy) {
  gx.width = gy.width = image.width;
  gx.height = gy.height = image.height;
  gx.data.assign(image.data.size(), 0.0f);
  gy.data.assign(image.data.size(), 0.0f);
  for (int y = 1; y + 1 < image.height; ++y) {
    for (int x = 1; x + 1 < image.width; ++x) {
      gx.at(x, y) = 0.5f * (image.at(x + 1, y) - image.at(x - 1, y));
      gy.at(x, y) = 0.5f * (image.at(x, y + 1) - image.at(x, y - 1));
    }
  }
}

}  // namespace bivo::odometry
