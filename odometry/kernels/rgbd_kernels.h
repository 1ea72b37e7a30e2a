#pragma once
// The per-pixel passes of RgbdOdometryProblem, in float over structure-of-arrays buffers
// (one array per quantity, one entry per reference pixel with valid depth = "term"):
//
//   warp             T_21 = x: transform, project, read the 2x2 cell of the interleaved
//                    [I, D] current image, bilinear residuals r_I, r_D (eq. `new definition
//                    of residual`), their image gradients, validity flags; fused with the
//                    objective sums F_j = sum w_j r_j^2 under the stored weights (evaluate()).
//   scale sums       one step of the robust scale's fixed point (t-distribution).
//   weigh            w_j from a WeightModel (the pluggable weight stage), F_j, trace(Omega_j).
//   normal equations weights (fused: the same WeightModel), Jacobian rows J = [c, q x c] and
//                    the lower triangle of sum w [J; r] [J; r]^T, which holds H, b and a.
//
// Every pass works on a range [begin, end) of terms whose begin is a multiple of
// kChunkTerms; the caller runs chunks on any number of threads and adds their sums in chunk
// order, so results do not depend on the thread count. Inside a chunk, float lane sums go
// to double every kFlushTerms terms. Buffers hold padded_terms(n) entries (padding: flags
// 0, residuals 0). Interfaces are plain C++ (no Eigen): the AVX2 translation unit is
// compiled with other flags than the rest.
#include <cstddef>
#include <cstdint>

#include "odometry/weight_model.h"

namespace bivo::odometry {

constexpr std::size_t kLaneGroup = 16;     // buffers are padded to a multiple of this (the widest lanes)
constexpr std::size_t kFlushTerms = 1024;  // float lane sums -> double
constexpr std::size_t kChunkTerms = 4096;  // one unit of parallel work
inline std::size_t padded_terms(std::size_t n) { return (n + kLaneGroup - 1) / kLaneGroup * kLaneGroup; }
inline int chunk_count(std::size_t n) { return static_cast<int>((n + kChunkTerms - 1) / kChunkTerms); }

// kAvx512Vl: the AVX2 kernels encoded with AVX-512VL (32 registers), bit-identical to kAvx2.
// kAvx512: sixteen lanes (AVX-512F), equal to kAvx2 up to float rounding (other lane sums).
enum class KernelIsa { kScalar, kAvx2, kAvx512Vl, kAvx512 };
const char* to_string(KernelIsa isa);

// Which objectives a pass builds (single / depth build one, the others both).
struct ObjectiveMask {
  bool intensity = true, depth = true;
};

// Where the image gradients of the Jacobians come from (RgbdProblemOptions::jacobian):
// the current image at y (exact), the reference image at x (inverse-compositional style,
// precomputed per level), or their mean (ESM).
enum class GradientSource { kCurrent, kReference, kAverage };

struct PoseF {
  float R[9];  // row-major
  float t[3];
};

// Reference-side terms of one level (computed once per level).
struct ReferenceArrays {
  const float *x = nullptr, *y = nullptr, *z = nullptr;  // p_i = z K^-1 [x_i; 1]
  const float* intensity = nullptr;                      // I_1(x_i)
  // fx dI_1/du, fy dI_1/dv, fx dD_1/du, fy dD_1/dv at x_i (null unless reference gradients are used)
  const float *gi_u = nullptr, *gi_v = nullptr, *gd_u = nullptr, *gd_v = nullptr;
  std::size_t count = 0;  // terms (arrays are padded beyond)
};

// Per-pose state of every term.
struct TermBuffers {
  float *r_i = nullptr, *r_d = nullptr;  // 0 where invalid
  // fx dI_2/du, fy dI_2/dv, fx dD_2/du, fy dD_2/dv at y_i (0 where invalid)
  float *gi_u = nullptr, *gi_v = nullptr, *gd_u = nullptr, *gd_v = nullptr;
  std::uint8_t* flags = nullptr;         // bit 0: r_I valid, bit 1: r_D valid
  float *w_i = nullptr, *w_d = nullptr;  // weights of the latest weight stage
  float* q = nullptr;  // the radial brightness regressor I_1 (rho_y^2 - rho_x^2) (WarpParams::rho2 only)
};

struct WarpParams {
  PoseF pose;
  float fx = 0, fy = 0, cx = 0, cy = 0;
  int width = 0, height = 0;
  const float* cells = nullptr;  // current level: [I, D] per pixel, row-major
  float occlusion_margin = 0.1f;
  float min_z = 1e-6f;
  ObjectiveMask objectives;
  GradientSource gradients = GradientSource::kCurrent;
  // r_D (and its Jacobian) divided by (z / 1 m)^p, z the reference term's depth: depth noise
  // that grows with depth (p = 2: Kinect-class disparity). 0: r_D as defined.
  int depth_noise_exponent = 0;
  // r_I = I_2(y) - ((gain + radial (rho_y^2 - rho_x^2)) I_1(x) + offset): the current image's
  // brightness relative to the reference's (RgbdProblemOptions::affine_brightness), rho the
  // distance to the principal point in normalized coordinates; 1, 0 and 0: r_I as defined.
  float gain = 1.0f, offset = 0.0f, radial = 0.0f;
  // rho_x^2 of every reference term: the radial model is on, its regressor stored in
  // TermBuffers::q (with r_I) for the fit; null: off (radial must be 0).
  const float* rho2 = nullptr;
  bool weighted_sums = false;  // also F_j = sum w_j r_j^2 with the weights in the buffers
  // false: only the sums (weighted_sums must be set), nothing written to the buffers, which
  // keep the previous warp: an evaluation that no linearization will reuse.
  bool store = true;
};

struct WarpSums {
  double f_i = 0, f_d = 0;    // weighted_sums only
  double ss_i = 0, ss_d = 0;  // sum r^2
  long long valid_i = 0, valid_d = 0;
  void add(const WarpSums& o);
};

// Per objective: packed lower triangle of sum w v v^T, v = [J_0..J_5, r]:
// H(i, j) = g[i (i + 1) / 2 + j] (j <= i <= 5), b(i) = g[21 + i], a = g[27].
struct GramSums {
  double g[28] = {};
  double weight_sum = 0;
  void add(const GramSums& o);
};
struct NormalSums {
  GramSums intensity, depth;
  void add(const NormalSums& o);
};
// One evaluation of the t-distribution scale's fixed-point map g (robust_weights.h) over the
// terms: sum = sum_k r_k^2 (nu + 1) / d_k, d_k = nu + r_k^2 inv_scale2, and slope =
// sum_k [r_k^2 (nu + 1) / d_k] e_k with e_k = r_k^2 inv_scale2 / d_k, so that with sigma^2 =
// 1 / inv_scale2 and n valid terms g = sum / n and dg/d(sigma^2) = slope / (n sigma^2) (for
// Newton's method on sigma^2 = g(sigma^2)). Invalid terms have r = 0 and add 0.
struct ScaleSums {
  double sum = 0, slope = 0;
  void add(const ScaleSums& o);
};
// One pass of the joint (bivariate t) scale's fixed point (joint_weights.h) over the terms
// valid in both objectives, r = (x, y) = (r_I, r_D), w = (nu + 2) / (nu + r^T P r) with
// P = S^-1: the moments sum w r r^T, and the sums of w^2 (r r^T)(r r^T) that make the
// moments' derivative in P (Newton's Jacobian).
struct JointScaleSums {
  double m_ii = 0, m_id = 0, m_dd = 0;                 // sum w x^2, w x y, w y^2
  double t40 = 0, t31 = 0, t22 = 0, t13 = 0, t04 = 0;  // sum w^2 x^p y^q
  long long count = 0;                                 // terms valid in both
  void add(const JointScaleSums& o);
};
struct WeighSums {
  double f_i = 0, f_d = 0, weight_sum_i = 0, weight_sum_d = 0;
  void add(const WeighSums& o);
};
// The brightness fit (affine_brightness.h) over the terms with a valid r_I: r on x = I_1 -
// kBrightnessCentre (centred: float lane sums of x^2 keep their digits), 1 and, with the
// radial term, q = I_1 (rho_y^2 - rho_x^2); w the stored w_I or 1.
constexpr float kBrightnessCentre = 128.0f;
struct BrightnessSums {
  double w = 0, wx = 0, wxx = 0, wr = 0, wxr = 0;
  double wq = 0, wxq = 0, wqq = 0, wqr = 0;  // radial only
  void add(const BrightnessSums& o);
};
struct BrightnessFit {
  const float* intensity = nullptr;  // I_1 of the reference terms
  bool weighted = false;
  bool radial = false;  // fit c too, on the stored TermBuffers::q
};
// The correction the fit found: r_I -= gain I_1 + offset + radial q.
struct BrightnessStep {
  float gain = 0.0f, offset = 0.0f, radial = 0.0f;
};

struct NormalParams {
  PoseF pose;
  ObjectiveMask objectives;
  int depth_noise_exponent = 0;  // as WarpParams
  float radial = 0.0f;           // as WarpParams: its term's derivative joins r_I's Jacobian
  // Gradients the Jacobians use: the buffers' (current / average) or the reference's.
  const float *gi_u = nullptr, *gi_v = nullptr, *gd_u = nullptr, *gd_v = nullptr;
};

// One image row of a level's reference terms (reference_terms.h): the pixels u whose depth z
// lies in [min_depth, max_depth], in order, back-projected in double and rounded to float:
// x = (u - cx) ifx z, y = ry z (ry = (v - cy) ify of the row), with z and the intensity.
struct ReferenceRow {
  const float *depth = nullptr, *intensity = nullptr;
  int width = 0;
  double cx = 0, ifx = 0, ry = 0, min_depth = 0, max_depth = 0;
};
struct ReferenceOut {
  float *x = nullptr, *y = nullptr, *z = nullptr, *intensity = nullptr;
};

// A rolling-shutter colour image moved to one instant (rolling_shutter.h,
// global_shutter_intensity): rows [v_begin, v_end) of `out` (holding the image already).
// Pixel u of row v, with its point P = z (u - cx) / fx, z (v - cy) / fy, z (z = depth[v w + u];
// a missing one takes the nearest valid one to its left in the row, else `fallback`; none when
// that is <= 0: the pixel keeps its value), is followed to the row that read it: q = R_r P + t_r with r = v, then r =
// the row where q projects (rounded, clamped); where both projections are in front of the camera and inside the image,
// out takes the image bilinearly at the second one. `pose` holds 12 floats per row: R row-major, then t. Bit-identical
// for every instruction set.
struct GlobalShutterParams {
  const float* intensity = nullptr;  // width x height, row-major
  const float* depth = nullptr;      // width x height [m], 0 = missing
  float fallback = 0.0f;             // [m]
  const float* pose = nullptr;       // 12 x height
  const float* columns = nullptr;    // u as float, width + kLaneGroup entries
  float* row_depth = nullptr;        // scratch, width + kLaneGroup entries
  float* out = nullptr;
  int width = 0, height = 0;
  float fx = 0, fy = 0, cx = 0, cy = 0;
};

// A depth image moved to another pose (depth_retiming.h, retime_depth): rows [v_begin, v_end)
// of `depth` splatted into `out` (holding +inf where nothing landed yet; a pixel keeps the
// smallest depth that lands on it, so rows may go in any order). `pose` holds R row-major, then
// t. Bit-identical for every instruction set.
struct RetimeDepthParams {
  const float* depth = nullptr;  // width x height [m], 0 = missing
  const float* rays = nullptr;   // (u - cx) / fx, width + kLaneGroup entries
  float pose[12] = {};
  float* row = nullptr;  // scratch, width + 2 + kLaneGroup entries
  float* out = nullptr;
  int width = 0, height = 0;
  float fx = 0, fy = 0, cx = 0, cy = 0;
};

struct KernelTable {
  KernelIsa isa;
  // Writes the row's terms from index k on; returns the index after the last. Bit-identical
  // for every instruction set.
  std::size_t (*reference_row)(const ReferenceRow&, const ReferenceOut&, std::size_t k);
  WarpSums (*warp)(const WarpParams&, const ReferenceArrays&, const TermBuffers&, std::size_t begin, std::size_t end);
  ScaleSums (*t_scale_sums)(const float* r, std::size_t begin, std::size_t end, float nu, float inv_scale2);
  JointScaleSums (*joint_scale_sums)(const JointScaleParams&, const TermBuffers&, std::size_t begin, std::size_t end);
  WeighSums (*weigh)(const WeightModel&, ObjectiveMask, const TermBuffers&, std::size_t begin, std::size_t end);
  // Sums for the brightness fit and its correction of the valid r_I, returning the new sum of r_I^2.
  BrightnessSums (*brightness_sums)(const BrightnessFit&, const TermBuffers&, std::size_t begin, std::size_t end);
  double (*correct_brightness)(const BrightnessFit&, const BrightnessStep&, const TermBuffers&, std::size_t begin,
                               std::size_t end);
  // rho^2 = x_n^2 + y_n^2 of terms [begin, end) (whole lane groups: entries up to the next multiple
  // of the lane width are written), x_n = x (1 / z) and the sum fused, as the warp forms rho_y^2, so
  // that the radial regressor is 0 at the identity. Bit-identical for every instruction set.
  void (*squared_radii)(const ReferenceArrays&, float* rho2, std::size_t begin, std::size_t end);
  NormalSums (*normal_equations)(const NormalParams&, const WeightModel&, const ReferenceArrays&, const TermBuffers&,
                                 std::size_t begin, std::size_t end);
  void (*global_shutter_rows)(const GlobalShutterParams&, int v_begin, int v_end);
  void (*retime_depth_rows)(const RetimeDepthParams&, int v_begin, int v_end);
};

// The best instruction set built in and supported by this CPU (AVX-512F sixteen lanes, else
// AVX-512VL, else AVX2 + FMA, else scalar).
const KernelTable& default_kernels();
bool kernels_available(KernelIsa isa);
// Throws bivo::Error when the instruction set is not built in or not supported here.
const KernelTable& kernels(KernelIsa isa);

}  // namespace bivo::odometry
