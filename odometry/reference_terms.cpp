#include "odometry/reference_terms.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "odometry/kernels/kernels.h"

namespace bivo::odometry {
namespace {

constexpr int kRowsPerChunk = 16;

// d/dx of a row at x: central difference, one-sided at the ends; with skip_missing only
// valid (> 0) neighbours are used and 0 is returned when neither side has one.
inline float row_derivative(const float* row, int x, int width, bool skip_missing) {
  const bool left = x > 0 && (!skip_missing || row[x - 1] > 0.0f);
  const bool right = x + 1 < width && (!skip_missing || row[x + 1] > 0.0f);
  if (left && right) return 0.5f * (row[x + 1] - row[x - 1]);
  if (right) return row[x + 1] - row[x];
  if (left) return row[x] - row[x - 1];
  return 0.0f;
}

// row_derivative's choice for a pixel m whose neighbours b (before) and a (after) both
// exist, depth-style (a neighbour counts when > 0), as selects on the comparisons so that
// the loops below vectorize (the same float operations).
inline float skipping_derivative(float b, float m, float a) {
  // Every candidate computed first, the selects only pick: with -fno-trapping-math on this
  // file (odometry/CMakeLists.txt) GCC vectorizes this.
  const float backward = m - b, forward = a - m, central = 0.5f * (a - b);
  float v = b > 0.0f ? backward : 0.0f;
  v = a > 0.0f ? forward : v;
  return ((b > 0.0f) & (a > 0.0f)) ? central : v;
}

// d/dx of a whole row into out[0, width): row_derivative at every x, the interior in one
// branch-free loop that the compiler vectorizes.
void row_derivatives(const float* row, int width, bool skip_missing, float scale, float* out) {
  if (width < 3) {
    for (int x = 0; x < width; ++x) out[x] = scale * row_derivative(row, x, width, skip_missing);
    return;
  }
  out[0] = scale * row_derivative(row, 0, width, skip_missing);
  out[width - 1] = scale * row_derivative(row, width - 1, width, skip_missing);
  if (!skip_missing) {
    for (int x = 1; x < width - 1; ++x) out[x] = scale * (0.5f * (row[x + 1] - row[x - 1]));
    return;
  }
  for (int x = 1; x < width - 1; ++x) out[x] = scale * skipping_derivative(row[x - 1], row[x], row[x + 1]);
}

// d/dy of image row y into out[0, width): column_derivative at every x of the row.
void column_derivatives(const ImageF& im, int y, bool skip_missing, float scale, float* out) {
  const std::size_t w = static_cast<std::size_t>(im.width);
  const float* c = im.data.data() + static_cast<std::size_t>(y) * w;
  const bool has_up = y > 0, has_down = y + 1 < im.height;
  const float* up = has_up ? c - w : c;  // a row that exists; unused when absent
  const float* down = has_down ? c + w : c;
  if (has_up && has_down) {
    if (skip_missing) {
      for (std::size_t x = 0; x < w; ++x) out[x] = scale * skipping_derivative(up[x], c[x], down[x]);
    } else {
      for (std::size_t x = 0; x < w; ++x) out[x] = scale * (0.5f * (down[x] - up[x]));
    }
    return;
  }
  // The first or the last row: one-sided where that side counts.
  for (std::size_t x = 0; x < w; ++x) {
    const float m = c[x], n = has_up ? up[x] : down[x];
    const bool counts = (has_up || has_down) && (!skip_missing || n > 0.0f);
    out[x] = scale * (!counts ? 0.0f : has_up ? m - n : n - m);
  }
}

// The float interval [lo, hi] holding exactly the floats z with min_depth <= double(z) <=
// max_depth (the test of reference_row), so that counting terms needs no double arithmetic.
struct FloatDepthRange {
  float lo, hi;
};

FloatDepthRange float_depth_range(double min_depth, double max_depth) {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  // One float step towards `to`, or nullopt at the end of the floats (nextafter stays put at
  // +-inf: a bound of inf must not loop).
  const auto step = [](float f, float to) -> std::optional<float> {
    const float g = std::nextafter(f, to);
    return g == f ? std::nullopt : std::optional<float>(g);
  };
  float lo = static_cast<float>(min_depth), hi = static_cast<float>(max_depth);
  while (double(lo) < min_depth && step(lo, kInf)) lo = *step(lo, kInf);
  for (auto below = step(lo, -kInf); below && double(*below) >= min_depth; below = step(lo, -kInf)) lo = *below;
  while (double(hi) > max_depth && step(hi, -kInf)) hi = *step(hi, -kInf);
  for (auto above = step(hi, kInf); above && double(*above) <= max_depth; above = step(hi, kInf)) hi = *above;
  return {lo, hi};
}

// How many of the n depths lie in [lo, hi] (NaN does not): branch-free, so GCC vectorizes it.
std::size_t count_in_range(const float* depth, std::size_t n, FloatDepthRange range) {
  std::size_t count = 0;
  for (std::size_t i = 0; i < n; ++i) count += (depth[i] >= range.lo) & (depth[i] <= range.hi);
  return count;
}

}  // namespace

ReferenceArrays ReferenceTerms::view() const {
  ReferenceArrays v;
  v.x = x.data();
  v.y = y.data();
  v.z = z.data();
  v.intensity = intensity.data();
  if (!gi_u.empty()) {
    v.gi_u = gi_u.data();
    v.gi_v = gi_v.data();
    v.gd_u = gd_u.data();
    v.gd_v = gd_v.data();
  }
  v.count = count;
  return v;
}

ReferenceTerms make_reference_terms(const RgbdLevel& reference, double min_depth, double max_depth, bool with_gradients,
                                    int threads, const KernelTable& kernels) {
  const ImageF& I = reference.intensity;
  const ImageF& D = reference.depth;
  const io::Intrinsics& K = reference.K;
  const double ifx = 1.0 / K.fx, ify = 1.0 / K.fy;
  const auto usable = [&](float z) { return double(z) >= min_depth && double(z) <= max_depth; };
  ReferenceTerms t;
  // Room for every pixel first (pooled memory, not touched beyond what is written), then the
  // arrays are cut to the padded term count and their padding zeroed.
  std::vector<PooledFloats*> arrays{&t.x, &t.y, &t.z, &t.intensity};
  if (with_gradients) arrays.insert(arrays.end(), {&t.gi_u, &t.gi_v, &t.gd_u, &t.gd_v});
  for (PooledFloats* v : arrays) v->reset(padded_terms(D.data.size()));
  const float fx = static_cast<float>(K.fx), fy = static_cast<float>(K.fy);
  const ReferenceOut out{t.x.data(), t.y.data(), t.z.data(), t.intensity.data()};
  // The terms of rows [y0, y1), the first at index k; returns the index after the last.
  const auto fill_rows = [&](int y0, int y1, std::size_t k) {
    // The row's four reference gradients at every pixel, then those of its terms.
    std::vector<float> gradient_rows(with_gradients ? 4 * static_cast<std::size_t>(D.width) : 0);
    float* const row_gi_u = gradient_rows.data();
    float* const row_gi_v = row_gi_u + (with_gradients ? D.width : 0);
    float* const row_gd_u = row_gi_v + (with_gradients ? D.width : 0);
    float* const row_gd_v = row_gd_u + (with_gradients ? D.width : 0);
    for (int y = y0; y < y1; ++y) {
      const float* drow = D.data.data() + static_cast<std::size_t>(y) * D.width;
      const float* irow = I.data.data() + static_cast<std::size_t>(y) * I.width;
      ReferenceRow row;
      row.depth = drow;
      row.intensity = irow;
      row.width = D.width;
      row.cx = K.cx;
      row.ifx = ifx;
      row.ry = (y - K.cy) * ify;
      row.min_depth = min_depth;
      row.max_depth = max_depth;
      const std::size_t row_begin = k;
      k = kernels.reference_row(row, out, k);
      if (!with_gradients) continue;
      row_derivatives(irow, I.width, false, fx, row_gi_u);
      column_derivatives(I, y, false, fy, row_gi_v);
      row_derivatives(drow, D.width, true, fx, row_gd_u);
      column_derivatives(D, y, true, fy, row_gd_v);
      // The same terms again, in the same order, for their reference gradients.
      float *const gi_u = t.gi_u.data(), *const gi_v = t.gi_v.data(), *const gd_u = t.gd_u.data(),
                   *const gd_v = t.gd_v.data();
      std::size_t g = row_begin;
      for (int x = 0; x < D.width; ++x) {
        if (!usable(drow[x])) continue;
        gi_u[g] = row_gi_u[x];
        gi_v[g] = row_gi_v[x];
        gd_u[g] = row_gd_u[x];
        gd_v[g] = row_gd_v[x];
        ++g;
      }
    }
    return k;
  };
  const int chunks = (D.height + kRowsPerChunk - 1) / kRowsPerChunk;
  std::size_t k = 0;
  const bool split = threads > 1 && chunks > 1;
  if (split) {
    // Threads: count each row chunk's terms, then every chunk writes from its own first
    // index: the same terms at the same indices as one pass in row order.
    std::vector<std::size_t> first(static_cast<std::size_t>(chunks) + 1, 0);
    const FloatDepthRange range = float_depth_range(min_depth, max_depth);
    for_each_chunk(chunks, threads, [&](int c) {
      const std::size_t w = static_cast<std::size_t>(D.width);
      const std::size_t y0 = static_cast<std::size_t>(c) * kRowsPerChunk;
      const std::size_t y1 = static_cast<std::size_t>(std::min(D.height, (c + 1) * kRowsPerChunk));
      first[static_cast<std::size_t>(c) + 1] = count_in_range(D.data.data() + y0 * w, (y1 - y0) * w, range);
    });
    for (int c = 0; c < chunks; ++c) first[static_cast<std::size_t>(c) + 1] += first[static_cast<std::size_t>(c)];
    for_each_chunk(chunks, threads, [&](int c) {
      fill_rows(c * kRowsPerChunk, std::min(D.height, (c + 1) * kRowsPerChunk), first[static_cast<std::size_t>(c)]);
    });
    k = first.back();
  } else {
    k = fill_rows(0, D.height, 0);
  }
  t.count = k;
  for (PooledFloats* v : arrays) {
    v->reset(padded_terms(k));
    v->fill_from(k, 0.0f);
  }
  return t;
}

std::vector<float> interleave_intensity_depth(const RgbdLevel& level) {
  const std::size_t n = level.intensity.data.size();
  std::vector<float> out(2 * n);
  const float* I = level.intensity.data.data();
  const float* D = level.depth.data.data();
  for (std::size_t i = 0; i < n; ++i) {
    out[2 * i] = I[i];
    out[2 * i + 1] = D[i];
  }
  return out;
}

}  // namespace bivo::odometry
