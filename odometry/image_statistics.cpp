#include "odometry/image_statistics.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "odometry/parallel_chunks.h"

namespace bivo::odometry {
namespace {

constexpr int kRowsPerChunk = 32;

int row_chunks(int rows) { return (rows + kRowsPerChunk - 1) / kRowsPerChunk; }

struct DifferenceSums {
  double sum_x = 0.0, sum_y = 0.0;
  long long used_x = 0, used_y = 0;
  void add(const DifferenceSums& o) {
    sum_x += o.sum_x;
    sum_y += o.sum_y;
    used_x += o.used_x;
    used_y += o.used_y;
  }
};

struct MomentSums {
  double s = 0.0, s2 = 0.0;
  long long n = 0;
  void add(const MomentSums& o) {
    s += o.s;
    s2 += o.s2;
    n += o.n;
  }
};

DifferenceSums difference_rows(const ImageF& im, bool skip_missing, int y0, int y1) {
  DifferenceSums d;
  const int w = im.width;
  for (int y = std::max(1, y0); y < std::min(y1, im.height - 1); ++y) {
    const float* up = im.data.data() + static_cast<std::size_t>(y - 1) * w;
    const float* row = up + w;
    const float* down = row + w;
    double sx = 0.0, sy = 0.0;
    int nx = 0, ny = 0;
    for (int x = 1; x + 1 < w; ++x) {
      const float l = row[x - 1], r = row[x + 1], u = up[x], b = down[x];
      const bool use_x = !skip_missing || (l > 0.0f && r > 0.0f);
      const bool use_y = !skip_missing || (u > 0.0f && b > 0.0f);
      sx += use_x ? std::abs(double(r) - l) : 0.0;
      sy += use_y ? std::abs(double(b) - u) : 0.0;
      nx += use_x;
      ny += use_y;
    }
    d.sum_x += sx;
    d.sum_y += sy;
    d.used_x += nx;
    d.used_y += ny;
  }
  return d;
}

// A float's bits as an unsigned integer with the same order as the floats.
inline std::uint32_t ordered_bits(float f) {
  std::uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  return (u & 0x80000000u) ? ~u : (u | 0x80000000u);
}

// The values of ranks k_lo <= k_hi (0-based) among the selected values, exactly: a histogram
// of the top 16 bits of ordered_bits() finds their buckets, whose few members nth_element sorts
// out (two passes over the image instead of a selection over all of it).
template <class Selected>
void select_ranks(const ImageF& im, const Selected& selected, std::size_t k_lo, std::size_t k_hi, float& lo,
                  float& hi) {
  std::vector<std::uint32_t> hist(1u << 16, 0u);
  for (float v : im.data) {
    if (selected(v)) ++hist[ordered_bits(v) >> 16];
  }
  std::size_t before = 0, bucket_lo = 0, bucket_hi = 0, base_lo = 0, base_hi = 0;
  bool found_lo = false;
  for (std::size_t b = 0; b < hist.size(); ++b) {
    if (!found_lo && before + hist[b] > k_lo) {
      bucket_lo = b;
      base_lo = before;
      found_lo = true;
    }
    if (before + hist[b] > k_hi) {
      bucket_hi = b;
      base_hi = before;
      break;
    }
    before += hist[b];
  }
  std::vector<float> in_lo, in_hi;
  for (float v : im.data) {
    if (!selected(v)) continue;
    const std::size_t b = ordered_bits(v) >> 16;
    if (b == bucket_lo) in_lo.push_back(v);
    if (b == bucket_hi && bucket_hi != bucket_lo) in_hi.push_back(v);
  }
  std::vector<float>& vh = bucket_hi == bucket_lo ? in_lo : in_hi;
  std::nth_element(in_lo.begin(), in_lo.begin() + static_cast<std::ptrdiff_t>(k_lo - base_lo), in_lo.end());
  lo = in_lo[k_lo - base_lo];
  std::nth_element(vh.begin(), vh.begin() + static_cast<std::ptrdiff_t>(k_hi - base_hi), vh.end());
  hi = vh[k_hi - base_hi];
}

}  // namespace

double complexity_metric(const ImageF& image, bool skip_missing, int threads) {
  const DifferenceSums d = sum_over_chunks<DifferenceSums>(
      static_cast<std::size_t>(row_chunks(image.height)), 1, threads, [&](std::size_t c, std::size_t) {
        const int y0 = static_cast<int>(c) * kRowsPerChunk;
        return difference_rows(image, skip_missing, y0, y0 + kRowsPerChunk);
      });
  return (d.used_x > 0 ? d.sum_x / d.used_x : 0.0) + (d.used_y > 0 ? d.sum_y / d.used_y : 0.0);
}

double variance(const ImageF& image, bool skip_missing, int threads) {
  const std::size_t n = image.data.size(), chunk = 1u << 14;
  const MomentSums m = sum_over_chunks<MomentSums>(n, chunk, threads, [&](std::size_t b, std::size_t e) {
    MomentSums s;
    for (std::size_t i = b; i < e; ++i) {
      const float v = image.data[i];
      if (skip_missing && !(v > 0.0f)) continue;
      s.s += v;
      s.s2 += double(v) * v;
      ++s.n;
    }
    return s;
  });
  if (m.n == 0) return 0.0;
  const double mean = m.s / m.n;
  return std::max(0.0, m.s2 / m.n - mean * mean);
}

double median(const ImageF& image, bool skip_missing) {
  const auto selected = [skip_missing](float v) { return !skip_missing || v > 0.0f; };
  std::size_t count = 0;
  for (float v : image.data) count += selected(v) ? 1 : 0;
  if (count == 0) return 0.0;
  const std::size_t mid = count / 2;
  float lower = 0.0f, upper = 0.0f;
  select_ranks(image, selected, count % 2 == 1 ? mid : mid - 1, mid, lower, upper);
  if (count % 2 == 1) return upper;
  return 0.5 * (double(lower) + upper);
}

FrameStatistics frame_statistics(const RgbdLevel& level, int threads) {
  FrameStatistics s;
  s.pi_intensity = complexity_metric(level.intensity, false, threads);
  s.pi_depth = complexity_metric(level.depth, true, threads);
  s.var_intensity = variance(level.intensity, false, threads);
  s.var_depth = variance(level.depth, true, threads);
  s.median_intensity = median(level.intensity, false);
  s.median_depth = median(level.depth, true);
  long long valid = 0;
  for (float d : level.depth.data) valid += d > 0.0f;
  s.valid_depth_fraction = level.depth.data.empty() ? 0.0 : double(valid) / level.depth.data.size();
  return s;
}

}  // namespace bivo::odometry
