#include "odometry/image_statistics.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "odometry/kernels/kernels.h"

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

// Histogram of the top 16 bits of ordered_bits() of the selected values, in buffers kept
// per thread (allocated once, not per frame). Neighbouring pixels often fall in the same
// bucket; counting even and odd pixels in two tables keeps consecutive increments of one
// bucket from waiting on each other.
template <class Selected>
const std::vector<std::uint32_t>& top_bits_histogram(const ImageF& im, const Selected& selected) {
  constexpr std::size_t kBuckets = 1u << 16;
  thread_local std::vector<std::uint32_t> hist, odd;
  hist.assign(kBuckets, 0u);
  odd.assign(kBuckets, 0u);
  const std::size_t n = im.data.size();
  const float* v = im.data.data();
  std::size_t i = 0;
  for (; i + 1 < n; i += 2) {
    if (selected(v[i])) ++hist[ordered_bits(v[i]) >> 16];
    if (selected(v[i + 1])) ++odd[ordered_bits(v[i + 1]) >> 16];
  }
  if (i < n && selected(v[i])) ++hist[ordered_bits(v[i]) >> 16];
  for (std::size_t b = 0; b < kBuckets; ++b) hist[b] += odd[b];
  return hist;
}

// The values of ranks k_lo <= k_hi (0-based) among the selected values, exactly: the
// histogram finds their buckets, whose few members nth_element sorts out (two passes over
// the image instead of a selection over all of it).
template <class Selected>
void select_ranks(const ImageF& im, const Selected& selected, const std::vector<std::uint32_t>& hist, std::size_t k_lo,
                  std::size_t k_hi, float& lo, float& hi) {
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
  in_lo.reserve(hist[bucket_lo]);
  if (bucket_hi != bucket_lo) in_hi.reserve(hist[bucket_hi]);
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

// Everything frame_statistics() sums, for rows [y0, y1), in ONE pass over the intensity and
// depth rows: differences for pi (interior pixels), moments for the variances, valid depths.
// Within a row, eight float lanes (the compiler vectorizes them) go to double per row.
struct FrameSums {
  DifferenceSums di, dd;
  MomentSums mi, md;
  void add(const FrameSums& o) {
    di.add(o.di);
    dd.add(o.dd);
    mi.add(o.mi);
    md.add(o.md);
  }
};

constexpr int kLanes = 8;

inline double lane_total(const float (&a)[kLanes]) {
  double s = 0.0;
  for (float v : a) s += v;
  return s;
}

// Eight float lanes as one GCC vector: one AVX2 register in the avx2 clone, two SSE ones in
// the baseline. Written with the vector operators because GCC left the per-lane loops of
// arrays (the previous form) scalar, with a compare and branch per pixel (~3 ns per pixel,
// twice the whole pyramid). Each lane does the same IEEE operations in the same order as
// before (x + y, x * y, select, clearing the sign bit for |x|; no contraction under
// -std=c++17), so the sums are the same bit for bit.
typedef float Lanes __attribute__((vector_size(4 * kLanes)));
typedef std::int32_t LaneMask __attribute__((vector_size(4 * kLanes)));

// By reference: a 32-byte vector passed or returned by value would change the baseline
// clone's ABI.
inline void load_lanes(Lanes& v, const float* p) { std::memcpy(&v, p, sizeof v); }

inline void abs_lanes(Lanes& v) {  // |v| lane by lane, as std::fabs: the sign bit cleared
  LaneMask bits;
  std::memcpy(&bits, &v, sizeof v);
  bits &= 0x7fffffff;
  std::memcpy(&v, &bits, sizeof v);
}

inline void store_lanes(float (&a)[kLanes], const Lanes& v) { std::memcpy(a, &v, sizeof a); }

// Built twice, for AVX2 and for the baseline, the loader picking one for this CPU (GCC
// function multi-versioning). Same operations in the same order in both (no FMA), so the
// same sums bit for bit.
__attribute__((target_clones("avx2", "default"))) FrameSums frame_rows(const ImageF& I, const ImageF& D, int y0,
                                                                       int y1) {
  FrameSums f;
  const int w = I.width, h = I.height;
  const Lanes zero = {};
  const Lanes one = zero + 1.0f;
  for (int y = y0; y < std::min(y1, h); ++y) {
    const float* irow = I.data.data() + static_cast<std::size_t>(y) * w;
    const float* drow = D.data.data() + static_cast<std::size_t>(y) * w;
    Lanes vsi = zero, vsi2 = zero, vsd = zero, vsd2 = zero, vnd = zero;
    int x = 0;
    for (; x + kLanes <= w; x += kLanes) {
      Lanes v, d;
      load_lanes(v, irow + x);
      load_lanes(d, drow + x);
      const LaneMask valid = d > zero;
      vsi += v;
      vsi2 += v * v;
      vsd += valid ? d : zero;
      vsd2 += valid ? d * d : zero;
      vnd += valid ? one : zero;
    }
    float si[kLanes], si2[kLanes], sd[kLanes], sd2[kLanes], nd[kLanes];
    store_lanes(si, vsi);
    store_lanes(si2, vsi2);
    store_lanes(sd, vsd);
    store_lanes(sd2, vsd2);
    store_lanes(nd, vnd);
    for (; x < w; ++x) {
      const float v = irow[x], d = drow[x];
      si[0] += v;
      si2[0] += v * v;
      if (d > 0.0f) {
        sd[0] += d;
        sd2[0] += d * d;
        nd[0] += 1.0f;
      }
    }
    f.mi.s += lane_total(si);
    f.mi.s2 += lane_total(si2);
    f.mi.n += w;
    f.md.s += lane_total(sd);
    f.md.s2 += lane_total(sd2);
    f.md.n += static_cast<long long>(lane_total(nd));
    if (y < 1 || y + 1 >= h) continue;
    const float *iu = irow - w, *ib = irow + w, *du = drow - w, *db = drow + w;
    Lanes vgxi = zero, vgyi = zero, vgxd = zero, vgyd = zero, vnxd = zero, vnyd = zero;
    x = 1;
    for (; x + kLanes <= w - 1; x += kLanes) {
      Lanes il, ir, iup, idown, dl, dr, dup, ddown;
      load_lanes(il, irow + x - 1);
      load_lanes(ir, irow + x + 1);
      load_lanes(iup, iu + x);
      load_lanes(idown, ib + x);
      load_lanes(dl, drow + x - 1);
      load_lanes(dr, drow + x + 1);
      load_lanes(dup, du + x);
      load_lanes(ddown, db + x);
      Lanes gx = ir - il, gy = idown - iup, hx = dr - dl, hy = ddown - dup;
      abs_lanes(gx);
      abs_lanes(gy);
      abs_lanes(hx);
      abs_lanes(hy);
      vgxi += gx;
      vgyi += gy;
      const LaneMask ux = (dl > zero) & (dr > zero);
      const LaneMask uy = (dup > zero) & (ddown > zero);
      vgxd += ux ? hx : zero;
      vgyd += uy ? hy : zero;
      vnxd += ux ? one : zero;
      vnyd += uy ? one : zero;
    }
    float gxi[kLanes], gyi[kLanes], gxd[kLanes], gyd[kLanes], nxd[kLanes], nyd[kLanes];
    store_lanes(gxi, vgxi);
    store_lanes(gyi, vgyi);
    store_lanes(gxd, vgxd);
    store_lanes(gyd, vgyd);
    store_lanes(nxd, vnxd);
    store_lanes(nyd, vnyd);
    for (; x < w - 1; ++x) {
      gxi[0] += std::fabs(irow[x + 1] - irow[x - 1]);
      gyi[0] += std::fabs(ib[x] - iu[x]);
      if (drow[x - 1] > 0.0f && drow[x + 1] > 0.0f) {
        gxd[0] += std::fabs(drow[x + 1] - drow[x - 1]);
        nxd[0] += 1.0f;
      }
      if (du[x] > 0.0f && db[x] > 0.0f) {
        gyd[0] += std::fabs(db[x] - du[x]);
        nyd[0] += 1.0f;
      }
    }
    f.di.sum_x += lane_total(gxi);
    f.di.sum_y += lane_total(gyi);
    f.di.used_x += w - 2;
    f.di.used_y += w - 2;
    f.dd.sum_x += lane_total(gxd);
    f.dd.sum_y += lane_total(gyd);
    f.dd.used_x += static_cast<long long>(lane_total(nxd));
    f.dd.used_y += static_cast<long long>(lane_total(nyd));
  }
  return f;
}

double metric_of(const DifferenceSums& d) {
  return (d.used_x > 0 ? d.sum_x / d.used_x : 0.0) + (d.used_y > 0 ? d.sum_y / d.used_y : 0.0);
}

double variance_of(const MomentSums& m) {
  if (m.n == 0) return 0.0;
  const double mean = m.s / m.n;
  return std::max(0.0, m.s2 / m.n - mean * mean);
}

}  // namespace

double complexity_metric(const ImageF& image, bool skip_missing, int threads) {
  const DifferenceSums d = sum_over_chunks<DifferenceSums>(
      static_cast<std::size_t>(row_chunks(image.height)), 1, threads, [&](std::size_t c, std::size_t) {
        const int y0 = static_cast<int>(c) * kRowsPerChunk;
        return difference_rows(image, skip_missing, y0, y0 + kRowsPerChunk);
      });
  return metric_of(d);
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
  return variance_of(m);
}

bool has_contrast(const ImageF& image, float range) {
  if (image.data.empty()) return false;
  const float first = image.data.front();
  return std::any_of(image.data.begin(), image.data.end(), [&](float v) { return !(std::fabs(v - first) < range); });
}

double median(const ImageF& image, bool skip_missing) {
  const auto selected = [skip_missing](float v) { return !skip_missing || v > 0.0f; };
  const std::vector<std::uint32_t>& hist = top_bits_histogram(image, selected);
  std::size_t count = 0;
  for (std::uint32_t c : hist) count += c;
  if (count == 0) return 0.0;
  const std::size_t mid = count / 2;
  float lower = 0.0f, upper = 0.0f;
  select_ranks(image, selected, hist, count % 2 == 1 ? mid : mid - 1, mid, lower, upper);
  if (count % 2 == 1) return upper;
  return 0.5 * (double(lower) + upper);
}

void add_medians(FrameStatistics& s, const RgbdLevel& level) {
  if (s.has_medians) return;
  s.median_intensity = median(level.intensity, false);
  s.median_depth = median(level.depth, true);
  s.has_medians = true;
}

FrameStatistics frame_statistics(const RgbdLevel& level, int threads, bool with_medians) {
  const ImageF& I = level.intensity;
  const ImageF& D = level.depth;
  FrameStatistics s;
  const FrameSums f = sum_over_chunks<FrameSums>(static_cast<std::size_t>(row_chunks(I.height)), 1, threads,
                                                 [&](std::size_t c, std::size_t) {
                                                   const int y0 = static_cast<int>(c) * kRowsPerChunk;
                                                   return frame_rows(I, D, y0, y0 + kRowsPerChunk);
                                                 });
  s.pi_intensity = metric_of(f.di);
  s.pi_depth = metric_of(f.dd);
  s.var_intensity = variance_of(f.mi);
  s.var_depth = variance_of(f.md);
  if (with_medians) add_medians(s, level);
  s.valid_depth_fraction = D.data.empty() ? 0.0 : double(f.md.n) / D.data.size();
  return s;
}

}  // namespace bivo::odometry
