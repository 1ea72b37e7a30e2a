#include "odometry/rgbd_pyramid.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <utility>

#include "odometry/kernels/kernels.h"
#include "solvers/error.h"

namespace bivo::odometry {

namespace {

constexpr int kRowsPerChunk = 16;

// Level images of dead pyramids (RgbdPyramid), per thread, at most kMaxSpareImages.
constexpr std::size_t kMaxSpareImages = 16;

// Set when this thread's spare list is gone (thread exit): pyramids destroyed after it
// (statics) free their images instead.
thread_local bool spares_destroyed = false;

struct SpareImages {
  std::vector<std::vector<float>> images;
  ~SpareImages() { spares_destroyed = true; }
};

std::vector<std::vector<float>>& spare_images() {
  thread_local SpareImages s;
  return s.images;
}

// n floats, not initialized when a spare image of at least n entries exists (callers write
// every entry): the smallest such, cut to n.
std::vector<float> image_storage(std::size_t n) {
  std::vector<float> out;
  if (!spares_destroyed) {
    std::vector<std::vector<float>>& spares = spare_images();
    auto best = spares.end();
    for (auto it = spares.begin(); it != spares.end(); ++it) {
      if (it->size() >= n && (best == spares.end() || it->size() < best->size())) best = it;
    }
    if (best != spares.end()) {
      out = std::move(*best);
      spares.erase(best);
    }
  }
  out.resize(n);  // shrinking writes nothing
  return out;
}

void recycle_levels(std::vector<RgbdLevel>& levels) {
  if (spares_destroyed) return;
  std::vector<std::vector<float>>& spares = spare_images();
  for (std::size_t l = 1; l < levels.size(); ++l) {
    for (ImageF* im : {&levels[l].intensity, &levels[l].depth}) {
      if (im->data.empty() || spares.size() >= kMaxSpareImages) continue;
      spares.push_back(std::move(im->data));
    }
  }
}

ImageF half_size(const ImageF& fine) {
  ImageF c;
  c.width = fine.width / 2;
  c.height = fine.height / 2;
  c.data = image_storage(static_cast<std::size_t>(c.width) * c.height);
  return c;
}

// The 2x2 reductions of one coarse pixel (the rows' remainder after the vector lanes below).
struct Mean4 {
  float operator()(float a, float b, float c, float d) const { return 0.25f * (a + b + c + d); }
};
constexpr Mean4 mean4{};

// Mean of the valid (> 0) depths only: averaging in a hole would invent a depth.
struct MeanValid4 {
  float operator()(float a, float b, float c, float d) const {
    const float sum = (a > 0.0f ? a : 0.0f) + (b > 0.0f ? b : 0.0f) + (c > 0.0f ? c : 0.0f) + (d > 0.0f ? d : 0.0f);
    const int count = (a > 0.0f) + (b > 0.0f) + (c > 0.0f) + (d > 0.0f);
    return count > 0 ? sum / static_cast<float>(count) : 0.0f;
  }
};
constexpr MeanValid4 mean_valid4{};

// Half resolution, rows [y0, y1) of the coarse image, each coarse pixel the reduction of its
// 2x2 fine block: eight pixels at a time as GCC vector operations, built for AVX2 and for the
// baseline (function multi-versioning; GCC left the plain per-pixel loop scalar). Each lane
// does the reduction's operations in its order ((a + b) + c) + d, the count of valid depths
// as a float sum of ones, exact), so the same images bit for bit.
typedef float Lanes __attribute__((vector_size(32)));
typedef std::int32_t LaneInts __attribute__((vector_size(32)));

// The 2x2 blocks of coarse pixels [x, x + 8): a, b from the upper fine row, c, d from the lower.
inline void load_blocks(const float* r0, const float* r1, int x, Lanes& a, Lanes& b, Lanes& c, Lanes& d) {
  Lanes p0, p1, q0, q1;
  std::memcpy(&p0, r0 + 2 * x, sizeof p0);
  std::memcpy(&p1, r0 + 2 * x + 8, sizeof p1);
  std::memcpy(&q0, r1 + 2 * x, sizeof q0);
  std::memcpy(&q1, r1 + 2 * x + 8, sizeof q1);
  const LaneInts even = {0, 2, 4, 6, 8, 10, 12, 14}, odd = {1, 3, 5, 7, 9, 11, 13, 15};
  a = __builtin_shuffle(p0, p1, even);
  b = __builtin_shuffle(p0, p1, odd);
  c = __builtin_shuffle(q0, q1, even);
  d = __builtin_shuffle(q0, q1, odd);
}

// Rows [y0, y1) of the coarse image: `lanes` on eight coarse pixels at a time, `pixel` on the
// rows' remainder. Always inlined into the two clones below, so that each compiles the lane
// operations for its own instruction set (a clone cannot be a template).
template <class LaneReduce, class PixelReduce>
__attribute__((always_inline)) inline void reduce_rows(const ImageF& fine, ImageF& coarse, int y0, int y1,
                                                       const LaneReduce& lanes, const PixelReduce& pixel) {
  for (int y = y0; y < y1; ++y) {
    const float* r0 = fine.data.data() + static_cast<std::size_t>(2 * y) * fine.width;
    const float* r1 = r0 + fine.width;
    float* out = coarse.data.data() + static_cast<std::size_t>(y) * coarse.width;
    int x = 0;
    for (; x + 8 <= coarse.width; x += 8) {
      Lanes a, b, c, d, m;
      load_blocks(r0, r1, x, a, b, c, d);
      lanes(a, b, c, d, m);
      std::memcpy(out + x, &m, sizeof m);
    }
    for (; x < coarse.width; ++x) out[x] = pixel(r0[2 * x], r0[2 * x + 1], r1[2 * x], r1[2 * x + 1]);
  }
}

// The lane forms of Mean4 and MeanValid4 (output by reference: see load_lanes in
// image_statistics.cpp on the baseline clone's ABI).
struct Mean4Lanes {
  __attribute__((always_inline)) void operator()(const Lanes& a, const Lanes& b, const Lanes& c, const Lanes& d,
                                                 Lanes& m) const {
    m = 0.25f * (a + b + c + d);
  }
};
struct MeanValid4Lanes {
  __attribute__((always_inline)) void operator()(const Lanes& a, const Lanes& b, const Lanes& c, const Lanes& d,
                                                 Lanes& m) const {
    const Lanes zero = {};
    const Lanes one = zero + 1.0f;
    const LaneInts va = a > zero, vb = b > zero, vc = c > zero, vd = d > zero;
    const Lanes sum = (va ? a : zero) + (vb ? b : zero) + (vc ? c : zero) + (vd ? d : zero);
    const Lanes count = (va ? one : zero) + (vb ? one : zero) + (vc ? one : zero) + (vd ? one : zero);
    m = count > zero ? sum / count : zero;
  }
};

__attribute__((target_clones("avx2", "default"))) void mean4_rows(const ImageF& fine, ImageF& coarse, int y0, int y1) {
  reduce_rows(fine, coarse, y0, y1, Mean4Lanes{}, mean4);
}

__attribute__((target_clones("avx2", "default"))) void mean_valid4_rows(const ImageF& fine, ImageF& coarse, int y0,
                                                                        int y1) {
  reduce_rows(fine, coarse, y0, y1, MeanValid4Lanes{}, mean_valid4);
}

void interleave_rows(const RgbdLevel& L, PooledFloats& out, int y0, int y1) {
  const std::size_t w = static_cast<std::size_t>(L.intensity.width);
  for (std::size_t i = static_cast<std::size_t>(y0) * w; i < static_cast<std::size_t>(y1) * w; ++i) {
    out[2 * i] = L.intensity.data[i];
    out[2 * i + 1] = L.depth.data[i];
  }
}

int row_chunks(int rows) { return (rows + kRowsPerChunk - 1) / kRowsPerChunk; }

}  // namespace

RgbdPyramid::~RgbdPyramid() { recycle_levels(levels); }

RgbdPyramid& RgbdPyramid::operator=(RgbdPyramid&& o) noexcept {
  if (this != &o) {
    recycle_levels(levels);
    timestamp = o.timestamp;
    depth_delay = o.depth_delay;
    levels = std::move(o.levels);
  }
  return *this;
}

ImageF downsample_intensity(const ImageF& fine) {
  ImageF c = half_size(fine);
  mean4_rows(fine, c, 0, c.height);
  return c;
}

ImageF downsample_depth(const ImageF& fine) {
  ImageF c = half_size(fine);
  mean_valid4_rows(fine, c, 0, c.height);
  return c;
}

RgbdPyramid build_pyramid(io::RgbdImage image, const io::Intrinsics& K, int levels, int threads, int finest_level) {
  if (levels < 1) throw Error("pyramid needs at least 1 level, got " + std::to_string(levels));
  const int cw = image.width >> (levels - 1), ch = image.height >> (levels - 1);
  if (cw < 8 || ch < 8) {
    throw Error("pyramid of " + std::to_string(levels) + " levels on a " + std::to_string(image.width) + "x" +
                std::to_string(image.height) + " image leaves a " + std::to_string(cw) + "x" + std::to_string(ch) +
                " coarsest level (minimum 8x8)");
  }
  RgbdPyramid p;
  p.timestamp = image.timestamp;
  p.depth_delay = image.depth_delay;
  p.levels.resize(static_cast<std::size_t>(levels));
  RgbdLevel& base = p.levels[0];
  base.level = 0;
  base.K = K;
  base.intensity.width = base.depth.width = image.width;
  base.intensity.height = base.depth.height = image.height;
  base.intensity.data = std::move(image.intensity);
  base.depth.data = std::move(image.depth);
  for (int l = 0; l < levels; ++l) {
    RgbdLevel& L = p.levels[static_cast<std::size_t>(l)];
    if (l > 0) {
      const RgbdLevel& fine = p.levels[static_cast<std::size_t>(l - 1)];
      L.level = l;
      L.K = K.at_level(l);
      L.intensity = half_size(fine.intensity);
      L.depth = half_size(fine.depth);
    }
    const bool interleave = l >= finest_level;
    if (interleave) L.intensity_depth.reset(2 * L.intensity.data.size());  // every entry written below
    const int rows = L.intensity.height;
    for_each_chunk(row_chunks(rows), threads, [&](int c) {
      const int y0 = c * kRowsPerChunk, y1 = std::min(rows, y0 + kRowsPerChunk);
      if (l > 0) {
        const RgbdLevel& fine = p.levels[static_cast<std::size_t>(l - 1)];
        mean4_rows(fine.intensity, L.intensity, y0, y1);
        mean_valid4_rows(fine.depth, L.depth, y0, y1);
      }
      if (interleave) interleave_rows(L, L.intensity_depth, y0, y1);
    });
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

RgbdPyramid pyramid_from_full_resolution(const RgbdPyramid& pyramid, ImageF intensity, ImageF depth) {
  RgbdPyramid out;
  out.timestamp = pyramid.timestamp;
  out.levels.resize(pyramid.levels.size());
  for (std::size_t l = 0; l < pyramid.levels.size(); ++l) {
    RgbdLevel& L = out.levels[l];
    L.level = pyramid.levels[l].level;
    L.K = pyramid.levels[l].K;
    if (l == 0) {
      L.intensity = std::move(intensity);
      L.depth = std::move(depth);
    } else {
      L.intensity = downsample_intensity(out.levels[l - 1].intensity);
      L.depth = downsample_depth(out.levels[l - 1].depth);
    }
  }
  return out;
}

}  // namespace bivo::odometry
