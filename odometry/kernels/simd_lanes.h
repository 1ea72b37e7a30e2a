// Lane types of the per-pixel kernels (rgbd_kernels_impl.h): ONE kernel source compiled for
// several instruction sets. No include guard on purpose: a kernel translation unit defines
// BIVO_KERNEL_NS (its own namespace, so the two builds of every inline function stay apart
// at link time) and includes this once, through rgbd_kernels_impl.h.
//
//   ScalarLanes  one float lane, plain C++: the build-time fallback and the reference of the
//                agreement tests (tests/test_odometry_kernels.cpp).
//   Avx2Lanes    eight float lanes, AVX2 + FMA; only where __AVX2__ and __FMA__ are defined
//                (rgbd_kernels_avx2.cpp is compiled with -mavx2 -mfma).
//   Avx512Lanes  sixteen float lanes, AVX-512F; only where __AVX512F__ is defined
//                (rgbd_kernels_avx512.cpp).
//
// F: a float per lane; M: a mask per lane; I: a 32-bit index per lane. Nothing here uses
// the standard library or Eigen, so no template of theirs is instantiated with AVX2 code.
#ifndef BIVO_KERNEL_NS
#error "define BIVO_KERNEL_NS before including odometry/kernels/simd_lanes.h"
#endif

#include <cstddef>
#include <cstdint>
#if (defined(__AVX2__) && defined(__FMA__)) || defined(__AVX512F__)
#include <immintrin.h>
#endif

namespace bivo::odometry {
namespace BIVO_KERNEL_NS {

// The 2x2 interpolation cell of every lane: intensity and depth at (x0, y0), (x0+1, y0),
// (x0, y0+1), (x0+1, y0+1), read from the interleaved [I, D] image of the current frame.
template <class F>
struct Cell {
  F i00, i10, i01, i11, d00, d10, d01, d11;
};

struct ScalarLanes {
  static constexpr int kWidth = 1;
  static constexpr bool kCompressesRows = false;
  using F = float;
  using M = bool;

  static F load(const float* p) { return *p; }
  static void store(float* p, F v) { *p = v; }
  static F set(float v) { return v; }
  static F fma(F a, F b, F c) { return a * b + c; }
  // 1 / a for a sum that tolerates float rounding (t_scale_sums): exact here.
  static F sum_reciprocal(F a) { return 1.0f / a; }
  static F select(M m, F a, F b) { return m ? a : b; }
  static M and_not(M a, M b) { return a && !b; }  // a & ~b
  static M all_lanes() { return true; }
  // Lanes k + j < n.
  static M lanes_below(std::size_t k, std::size_t n) { return k < n; }
  static M flag(const std::uint8_t* p, std::uint8_t bit) { return (*p & bit) != 0; }
  static void store_flags(std::uint8_t* p, M a, M b) { *p = static_cast<std::uint8_t>((a ? 1 : 0) | (b ? 2 : 0)); }
  static int count(M m) { return m ? 1 : 0; }
  static double sum(F v) { return v; }
  // Each lane truncated toward zero to index[0..kWidth) (lanes out of int range: unspecified).
  static void truncate(F v, std::int32_t* index) { *index = static_cast<std::int32_t>(v); }
  // base[index[j]] in lane j.
  static F gather(const float* base, const std::int32_t* index) { return base[*index]; }

  // Pixel cell of (u, v) (valid lanes have 0 <= u < width - 1, 0 <= v < height - 1), one
  // index per lane stored at index[0..kWidth), and the fractions inside it; masked-off lanes
  // get index 0 (a readable cell).
  static void cell_of(F u, F v, M valid, int width, std::int32_t* index, F& a, F& b) {
    if (!valid) {
      *index = 0;
      a = b = 0.0f;
      return;
    }
    const int x0 = static_cast<int>(u), y0 = static_cast<int>(v);
    *index = y0 * width + x0;
    a = u - static_cast<float>(x0);
    b = v - static_cast<float>(y0);
  }
  // The cells of the lanes whose indices (cell_of) are stored at k[0], k[1], ...
  static Cell<F> load_cell(const float* interleaved, const std::int32_t* k, int width) {
    const float* top = interleaved + 2 * static_cast<std::ptrdiff_t>(*k);
    const float* bottom = top + 2 * static_cast<std::ptrdiff_t>(width);
    return {top[0], top[2], bottom[0], bottom[2], top[1], top[3], bottom[1], bottom[3]};
  }
};

#if defined(__AVX2__) && defined(__FMA__)
struct Avx2F {
  __m256 v;
};
struct Avx2M {
  __m256 m;
};
inline Avx2F operator+(Avx2F a, Avx2F b) { return {_mm256_add_ps(a.v, b.v)}; }
inline Avx2F operator-(Avx2F a, Avx2F b) { return {_mm256_sub_ps(a.v, b.v)}; }
inline Avx2F operator*(Avx2F a, Avx2F b) { return {_mm256_mul_ps(a.v, b.v)}; }
inline Avx2F operator/(Avx2F a, Avx2F b) { return {_mm256_div_ps(a.v, b.v)}; }
inline Avx2F operator-(Avx2F a) { return {_mm256_xor_ps(a.v, _mm256_set1_ps(-0.0f))}; }
inline Avx2M operator<(Avx2F a, Avx2F b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_LT_OQ)}; }
inline Avx2M operator>(Avx2F a, Avx2F b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_GT_OQ)}; }
inline Avx2M operator<=(Avx2F a, Avx2F b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_LE_OQ)}; }
inline Avx2M operator>=(Avx2F a, Avx2F b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_GE_OQ)}; }
inline Avx2M operator&(Avx2M a, Avx2M b) { return {_mm256_and_ps(a.m, b.m)}; }
inline Avx2M operator|(Avx2M a, Avx2M b) { return {_mm256_or_ps(a.m, b.m)}; }

struct Avx2Lanes {
  static constexpr int kWidth = 8;
  static constexpr bool kCompressesRows = false;
  using F = Avx2F;
  using M = Avx2M;

  static F load(const float* p) { return {_mm256_loadu_ps(p)}; }
  static void store(float* p, F v) { _mm256_storeu_ps(p, v.v); }
  static F set(float v) { return {_mm256_set1_ps(v)}; }
  static F fma(F a, F b, F c) { return {_mm256_fmadd_ps(a.v, b.v, c.v)}; }
  static F sum_reciprocal(F a) { return {_mm256_div_ps(_mm256_set1_ps(1.0f), a.v)}; }
  static F select(M m, F a, F b) { return {_mm256_blendv_ps(b.v, a.v, m.m)}; }
  static M and_not(M a, M b) { return {_mm256_andnot_ps(b.m, a.m)}; }
  static M all_lanes() { return {_mm256_castsi256_ps(_mm256_set1_epi32(-1))}; }
  static M lanes_below(std::size_t k, std::size_t n) {
    const long long left = static_cast<long long>(n) - static_cast<long long>(k);
    const int room = left <= 0 ? 0 : (left >= 8 ? 8 : static_cast<int>(left));
    const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    return {_mm256_castsi256_ps(_mm256_cmpgt_epi32(_mm256_set1_epi32(room), lane))};
  }
  static M flag(const std::uint8_t* p, std::uint8_t bit) {
    const __m256i bytes = _mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p)));
    const __m256i b = _mm256_set1_epi32(bit);
    return {_mm256_castsi256_ps(_mm256_cmpeq_epi32(_mm256_and_si256(bytes, b), b))};
  }
  static void store_flags(std::uint8_t* p, M a, M b) {
    const __m256i bits = _mm256_or_si256(_mm256_and_si256(_mm256_castps_si256(a.m), _mm256_set1_epi32(1)),
                                         _mm256_and_si256(_mm256_castps_si256(b.m), _mm256_set1_epi32(2)));
    // 8 x int32 (each 0..3) -> 8 bytes.
    const __m128i lo = _mm256_castsi256_si128(bits), hi = _mm256_extracti128_si256(bits, 1);
    const __m128i words = _mm_packs_epi32(lo, hi);
    const __m128i bytes = _mm_packus_epi16(words, words);
    _mm_storel_epi64(reinterpret_cast<__m128i*>(p), bytes);
  }
  static int count(M m) { return __builtin_popcount(static_cast<unsigned>(_mm256_movemask_ps(m.m))); }
  // Fixed order (lane 0 + lane 1 + ...), in double: sums are reproducible bit for bit.
  static void truncate(F v, std::int32_t* index) {
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(index), _mm256_cvttps_epi32(v.v));
  }
  static F gather(const float* base, const std::int32_t* index) {
    return {_mm256_i32gather_ps(base, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(index)), 4)};
  }
  static double sum(F v) {
    alignas(32) float l[8];
    _mm256_store_ps(l, v.v);
    double s = 0.0;
    for (int j = 0; j < 8; ++j) s += l[j];
    return s;
  }

  static void cell_of(F u, F v, M valid, int width, std::int32_t* index, F& a, F& b) {
    const __m256 x0 = _mm256_floor_ps(u.v), y0 = _mm256_floor_ps(v.v);
    const __m256i xi = _mm256_cvttps_epi32(x0), yi = _mm256_cvttps_epi32(y0);
    const __m256i k = _mm256_add_epi32(_mm256_mullo_epi32(yi, _mm256_set1_epi32(width)), xi);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(index), _mm256_and_si256(k, _mm256_castps_si256(valid.m)));
    a = {_mm256_and_ps(_mm256_sub_ps(u.v, x0), valid.m)};
    b = {_mm256_and_ps(_mm256_sub_ps(v.v, y0), valid.m)};
  }
  // Each lane's cell is two 16-byte rows [I, D, I_right, D_right]; lanes j and j + 4 share a
  // 256-bit register, and one 4x4 transpose per row turns rows into lane vectors.
  static Cell<F> load_cell(const float* interleaved, const std::int32_t* k, int width) {
    const std::ptrdiff_t below = 2 * static_cast<std::ptrdiff_t>(width);
    __m256 top[4], bottom[4];
    for (int j = 0; j < 4; ++j) {
      const float* lo = interleaved + 2 * static_cast<std::ptrdiff_t>(k[j]);
      const float* hi = interleaved + 2 * static_cast<std::ptrdiff_t>(k[j + 4]);
      top[j] = _mm256_loadu2_m128(hi, lo);
      bottom[j] = _mm256_loadu2_m128(hi + below, lo + below);
    }
    Cell<F> c;
    transpose(top, c.i00, c.d00, c.i10, c.d10);
    transpose(bottom, c.i01, c.d01, c.i11, c.d11);
    return c;
  }

 private:
  static void transpose(const __m256 r[4], F& e0, F& e1, F& e2, F& e3) {
    const __m256 t0 = _mm256_unpacklo_ps(r[0], r[1]), t1 = _mm256_unpacklo_ps(r[2], r[3]);
    const __m256 t2 = _mm256_unpackhi_ps(r[0], r[1]), t3 = _mm256_unpackhi_ps(r[2], r[3]);
    e0 = {_mm256_shuffle_ps(t0, t1, 0x44)};
    e1 = {_mm256_shuffle_ps(t0, t1, 0xEE)};
    e2 = {_mm256_shuffle_ps(t2, t3, 0x44)};
    e3 = {_mm256_shuffle_ps(t2, t3, 0xEE)};
  }
};
#endif

#if defined(__AVX512F__)
// Sixteen float lanes in one 512-bit register, masks in k registers. On a CPU with full-width
// AVX-512 units (AMD Zen 5) a pass does twice the lanes per instruction of Avx2Lanes; the
// lane sums are those of sixteen lanes and the t-scale sums use an approximate reciprocal
// (sum_reciprocal), so results agree with the eight-lane kernels to float rounding, not bit
// for bit.
struct Avx512F {
  __m512 v;
};
struct Avx512M {
  __mmask16 m;
};
inline Avx512F operator+(Avx512F a, Avx512F b) { return {_mm512_add_ps(a.v, b.v)}; }
inline Avx512F operator-(Avx512F a, Avx512F b) { return {_mm512_sub_ps(a.v, b.v)}; }
inline Avx512F operator*(Avx512F a, Avx512F b) { return {_mm512_mul_ps(a.v, b.v)}; }
inline Avx512F operator/(Avx512F a, Avx512F b) { return {_mm512_div_ps(a.v, b.v)}; }
inline Avx512F operator-(Avx512F a) {
  return {_mm512_castsi512_ps(_mm512_xor_si512(_mm512_castps_si512(a.v), _mm512_set1_epi32(INT32_MIN)))};
}
inline Avx512M operator<(Avx512F a, Avx512F b) { return {_mm512_cmp_ps_mask(a.v, b.v, _CMP_LT_OQ)}; }
inline Avx512M operator>(Avx512F a, Avx512F b) { return {_mm512_cmp_ps_mask(a.v, b.v, _CMP_GT_OQ)}; }
inline Avx512M operator<=(Avx512F a, Avx512F b) { return {_mm512_cmp_ps_mask(a.v, b.v, _CMP_LE_OQ)}; }
inline Avx512M operator>=(Avx512F a, Avx512F b) { return {_mm512_cmp_ps_mask(a.v, b.v, _CMP_GE_OQ)}; }
inline Avx512M operator&(Avx512M a, Avx512M b) { return {static_cast<__mmask16>(a.m & b.m)}; }
inline Avx512M operator|(Avx512M a, Avx512M b) { return {static_cast<__mmask16>(a.m | b.m)}; }

struct Avx512Lanes {
  static constexpr int kWidth = 16;
  static constexpr bool kCompressesRows = true;
  using F = Avx512F;
  using M = Avx512M;

  static F load(const float* p) { return {_mm512_loadu_ps(p)}; }
  static void store(float* p, F v) { _mm512_storeu_ps(p, v.v); }
  static F set(float v) { return {_mm512_set1_ps(v)}; }
  static F fma(F a, F b, F c) { return {_mm512_fmadd_ps(a.v, b.v, c.v)}; }
  // 1 / a within ~1 ulp for a sum that tolerates float rounding (t_scale_sums, whose pass
  // the division's throughput bounded: one VDIVPS per sixteen terms and little else):
  // VRCP14PS (relative error < 2^-14, its bits are the CPU's) and one Newton step. Not
  // correctly rounded, so not bit-identical to the eight-lane kernels, which divide.
  static F sum_reciprocal(F a) {
    const __m512 x = _mm512_rcp14_ps(a.v);
    return {_mm512_fmadd_ps(x, _mm512_fnmadd_ps(a.v, x, _mm512_set1_ps(1.0f)), x)};
  }
  static F select(M m, F a, F b) { return {_mm512_mask_blend_ps(m.m, b.v, a.v)}; }
  static M and_not(M a, M b) { return {static_cast<__mmask16>(a.m & ~b.m)}; }
  static M all_lanes() { return {static_cast<__mmask16>(0xFFFF)}; }
  static M lanes_below(std::size_t k, std::size_t n) {
    const long long left = static_cast<long long>(n) - static_cast<long long>(k);
    const int room = left <= 0 ? 0 : (left >= 16 ? 16 : static_cast<int>(left));
    return {static_cast<__mmask16>((1u << room) - 1u)};
  }
  static M flag(const std::uint8_t* p, std::uint8_t bit) {
    const __m512i bytes = _mm512_cvtepu8_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p)));
    return {_mm512_test_epi32_mask(bytes, _mm512_set1_epi32(bit))};
  }
  static void store_flags(std::uint8_t* p, M a, M b) {
    const __m512i bits = _mm512_or_si512(_mm512_maskz_mov_epi32(a.m, _mm512_set1_epi32(1)),
                                         _mm512_maskz_mov_epi32(b.m, _mm512_set1_epi32(2)));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(p), _mm512_cvtepi32_epi8(bits));  // 16 x int32 -> 16 bytes
  }
  static int count(M m) { return __builtin_popcount(static_cast<unsigned>(m.m)); }
  // Fixed order (lane 0 + lane 1 + ...), in double: sums are reproducible bit for bit.
  static void truncate(F v, std::int32_t* index) { _mm512_storeu_si512(index, _mm512_cvttps_epi32(v.v)); }
  static F gather(const float* base, const std::int32_t* index) {
    return {_mm512_i32gather_ps(_mm512_loadu_si512(index), base, 4)};
  }
  static double sum(F v) {
    alignas(64) float l[16];
    _mm512_store_ps(l, v.v);
    double s = 0.0;
    for (int j = 0; j < 16; ++j) s += l[j];
    return s;
  }

  // reference_row (rgbd_kernels_impl.h) over the row's whole groups of sixteen pixels: the
  // same double operations in the same order, the usable lanes compressed to the front and
  // stored under a mask (a store of all sixteen would write into the next row chunk, which
  // another thread may be filling). Returns the first pixel not done; k moves on.
  static int reference_row_groups(const ReferenceRow& row, const ReferenceOut& out, std::size_t& k) {
    const __m512d iota = _mm512_setr_pd(0, 1, 2, 3, 4, 5, 6, 7);
    const __m512d cx = _mm512_set1_pd(row.cx), ifx = _mm512_set1_pd(row.ifx), ry = _mm512_set1_pd(row.ry);
    const __m512d lo = _mm512_set1_pd(row.min_depth), hi = _mm512_set1_pd(row.max_depth);
    int u = 0;
    for (; u + 16 <= row.width; u += 16) {
      const __m512 zf = _mm512_loadu_ps(row.depth + u);
      const __m512d z[2] = {_mm512_cvtps_pd(_mm512_castps512_ps256(zf)),
                            _mm512_cvtps_pd(_mm256_castpd_ps(_mm512_extractf64x4_pd(_mm512_castps_pd(zf), 1)))};
      __m256 x[2], y[2];
      unsigned m = 0;
      for (int h = 0; h < 2; ++h) {
        m |= static_cast<unsigned>(_mm512_cmp_pd_mask(z[h], lo, _CMP_GE_OQ) & _mm512_cmp_pd_mask(z[h], hi, _CMP_LE_OQ))
             << (8 * h);
        const __m512d col = _mm512_add_pd(_mm512_set1_pd(static_cast<double>(u + 8 * h)), iota);
        x[h] = _mm512_cvtpd_ps(_mm512_mul_pd(_mm512_mul_pd(_mm512_sub_pd(col, cx), ifx), z[h]));
        y[h] = _mm512_cvtpd_ps(_mm512_mul_pd(ry, z[h]));
      }
      if (m == 0) continue;
      const __mmask16 keep = static_cast<__mmask16>(m);
      const __mmask16 front = static_cast<__mmask16>((1u << __builtin_popcount(m)) - 1u);
      const auto put = [&](float* p, __m512 v) {
        _mm512_mask_storeu_ps(p + k, front, _mm512_maskz_compress_ps(keep, v));
      };
      put(out.x, join(x[0], x[1]));
      put(out.y, join(y[0], y[1]));
      put(out.z, zf);
      put(out.intensity, _mm512_loadu_ps(row.intensity + u));
      k += static_cast<std::size_t>(__builtin_popcount(m));
    }
    return u;
  }

  static void cell_of(F u, F v, M valid, int width, std::int32_t* index, F& a, F& b) {
    const __m512 x0 = _mm512_roundscale_ps(u.v, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
    const __m512 y0 = _mm512_roundscale_ps(v.v, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
    const __m512i xi = _mm512_cvttps_epi32(x0), yi = _mm512_cvttps_epi32(y0);
    const __m512i k = _mm512_add_epi32(_mm512_mullo_epi32(yi, _mm512_set1_epi32(width)), xi);
    _mm512_storeu_si512(index, _mm512_maskz_mov_epi32(valid.m, k));
    a = {_mm512_maskz_sub_ps(valid.m, u.v, x0)};
    b = {_mm512_maskz_sub_ps(valid.m, v.v, y0)};
  }
  // As Avx2Lanes::load_cell with four 128-bit quarters: register j holds the cell rows of
  // lanes j, j + 4, j + 8, j + 12, and the per-quarter 4x4 transpose gives lane vectors.
  static Cell<F> load_cell(const float* interleaved, const std::int32_t* k, int width) {
    const std::ptrdiff_t below = 2 * static_cast<std::ptrdiff_t>(width);
    __m512 top[4], bottom[4];
    for (int j = 0; j < 4; ++j) {
      const float* q[4];
      for (int h = 0; h < 4; ++h) q[h] = interleaved + 2 * static_cast<std::ptrdiff_t>(k[j + 4 * h]);
      top[j] = quarters(q[0], q[1], q[2], q[3]);
      bottom[j] = quarters(q[0] + below, q[1] + below, q[2] + below, q[3] + below);
    }
    Cell<F> c;
    transpose(top, c.i00, c.d00, c.i10, c.d10);
    transpose(bottom, c.i01, c.d01, c.i11, c.d11);
    return c;
  }

 private:
  static __m512 join(__m256 low, __m256 high) {
    return _mm512_castpd_ps(
        _mm512_insertf64x4(_mm512_castps_pd(_mm512_castps256_ps512(low)), _mm256_castps_pd(high), 1));
  }
  static __m512 quarters(const float* q0, const float* q1, const float* q2, const float* q3) {
    __m512 r = _mm512_castps128_ps512(_mm_loadu_ps(q0));
    r = _mm512_insertf32x4(r, _mm_loadu_ps(q1), 1);
    r = _mm512_insertf32x4(r, _mm_loadu_ps(q2), 2);
    return _mm512_insertf32x4(r, _mm_loadu_ps(q3), 3);
  }
  static void transpose(const __m512 r[4], F& e0, F& e1, F& e2, F& e3) {
    const __m512 t0 = _mm512_unpacklo_ps(r[0], r[1]), t1 = _mm512_unpacklo_ps(r[2], r[3]);
    const __m512 t2 = _mm512_unpackhi_ps(r[0], r[1]), t3 = _mm512_unpackhi_ps(r[2], r[3]);
    e0 = {_mm512_shuffle_ps(t0, t1, 0x44)};
    e1 = {_mm512_shuffle_ps(t0, t1, 0xEE)};
    e2 = {_mm512_shuffle_ps(t2, t3, 0x44)};
    e3 = {_mm512_shuffle_ps(t2, t3, 0xEE)};
  }
};
#endif

}  // namespace BIVO_KERNEL_NS
}  // namespace bivo::odometry
