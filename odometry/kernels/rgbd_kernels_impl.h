// The per-pixel kernels (rgbd_kernels.h) as templates over a lane type (simd_lanes.h).
// Included once by each kernel translation unit, inside its own namespace BIVO_KERNEL_NS
// (rgbd_kernels_scalar.cpp, rgbd_kernels_avx2.cpp, rgbd_kernels_avx512vl.cpp,
// rgbd_kernels_avx512.cpp); no include guard on purpose.
//
// Formulas (docs/odometry.md "Residuals and Jacobians"), per term with reference point p:
//   q = R p + t,  y = (fx q_x / q_z + cx, fy q_y / q_z + cy),  (x0, y0) = floor(y), (a, b) = y - (x0, y0)
//   I_2(y) = lerp(b, lerp(a, I00, I10), lerp(a, I01, I11))        (same for D_2)
//   r_I = I_2(y) - I_1(x),  r_D = D_2(y) - q_z
//   fx dI_2/du = fx lerp(b, I10 - I00, I11 - I01),  fy dI_2/dv = fy lerp(a, I01 - I00, I11 - I10)
//   c = (g_u / q_z, g_v / q_z, -(g_u q_x + g_v q_y) / q_z^2) (- e_z for r_D),  J = [c, q x c]
//   with a depth noise exponent p, r_D and its J times s = (1 / z)^p, z the reference depth
#include "odometry/kernels/rgbd_kernels.h"
#include "odometry/kernels/simd_lanes.h"

namespace bivo::odometry {
namespace BIVO_KERNEL_NS {

// Lane groups staged in L1 between two loops: the warp's cells, the Jacobian rows before the
// Gram update.
constexpr std::size_t kBlockTerms = 256;

template <class V>
struct LanePose {
  typename V::F R[9], t[3];
  explicit LanePose(const PoseF& p) {
    for (int i = 0; i < 9; ++i) R[i] = V::set(p.R[i]);
    for (int i = 0; i < 3; ++i) t[i] = V::set(p.t[i]);
  }
  void apply(typename V::F x, typename V::F y, typename V::F z, typename V::F& qx, typename V::F& qy,
             typename V::F& qz) const {
    qx = V::fma(R[0], x, V::fma(R[1], y, V::fma(R[2], z, t[0])));
    qy = V::fma(R[3], x, V::fma(R[4], y, V::fma(R[5], z, t[1])));
    qz = V::fma(R[6], x, V::fma(R[7], y, V::fma(R[8], z, t[2])));
  }
};

template <class V>
inline typename V::F lerp(typename V::F s, typename V::F a, typename V::F b) {
  return V::fma(s, b - a, a);
}

// The depth residual's scale s = (1 / z)^p for reference depths z (p in {1, 2}).
template <class V>
inline typename V::F depth_noise_scale(typename V::F z, int exponent) {
  const typename V::F iz = V::set(1.0f) / z;
  return exponent == 1 ? iz : exponent == 2 ? iz * iz : iz * iz * iz;
}

// kStore false: the same sums, in the same order, without the stores and the gradients.
// Two loops per block of kBlockTerms: the first projects the points and finds their cells
// (indices, fractions, masks staged in L1), the second reads the cells and forms the
// residuals. Within one loop the lane groups are independent, so the out-of-order core
// overlaps several of them; as one loop, each group's chain (transform, division, cell
// index, the cell's sixteen loads and their transpose) was too long to overlap two.
// The same operations in the same order: the same bits.
template <class V, bool kStore>
WarpSums warp_pass(const WarpParams& p, const ReferenceArrays& ref, const TermBuffers& out, std::size_t begin,
                   std::size_t end) {
  using F = typename V::F;
  using M = typename V::M;
  constexpr int kGroups = static_cast<int>(kBlockTerms) / V::kWidth;
  const LanePose<V> T(p.pose);
  const F zero = V::set(0.0f), half = V::set(0.5f), one = V::set(1.0f);
  const F fx = V::set(p.fx), fy = V::set(p.fy), cx = V::set(p.cx), cy = V::set(p.cy);
  const F u_max = V::set(static_cast<float>(p.width - 1)), v_max = V::set(static_cast<float>(p.height - 1));
  const F min_z = V::set(p.min_z), margin = V::set(p.occlusion_margin);
  const bool want_i = p.objectives.intensity, want_d = p.objectives.depth;
  const bool current_gradients = kStore && p.gradients != GradientSource::kReference;
  const bool average = p.gradients == GradientSource::kAverage;
  alignas(64) std::int32_t stage_index[kBlockTerms];  // kWidth per lane group
  alignas(64) F stage_a[kGroups], stage_b[kGroups], stage_qz[kGroups], stage_radial[kGroups];
  const bool radial = want_i && p.rho2 != nullptr;
  M stage_inside[kGroups];
  WarpSums sums;
  for (std::size_t s = begin; s < end; s += kFlushTerms) {
    const std::size_t s_end = s + kFlushTerms < end ? s + kFlushTerms : end;
    F f_i = zero, f_d = zero, ss_i = zero, ss_d = zero;
    for (std::size_t bs = s; bs < s_end; bs += kBlockTerms) {
      const std::size_t b_end = bs + kBlockTerms < s_end ? bs + kBlockTerms : s_end;
      const int groups = static_cast<int>((b_end - bs + V::kWidth - 1) / V::kWidth);
      for (int g = 0; g < groups; ++g) {
        const std::size_t k = bs + static_cast<std::size_t>(g) * V::kWidth;
        F qx, qy, qz;
        T.apply(V::load(ref.x + k), V::load(ref.y + k), V::load(ref.z + k), qx, qy, qz);
        const M front = (qz > min_z) & V::lanes_below(k, ref.count);
        const F iz = one / qz;
        const F u = V::fma(fx * qx, iz, cx), v = V::fma(fy * qy, iz, cy);
        const M inside = front & (u >= zero) & (v >= zero) & (u < u_max) & (v < v_max);
        V::cell_of(u, v, inside, p.width, stage_index + g * V::kWidth, stage_a[g], stage_b[g]);
        stage_qz[g] = qz;
        stage_inside[g] = inside;
        if (radial) {
          // The radial brightness regressor I_1 (rho_y^2 - rho_x^2), 0 outside (q_z may be 0).
          const F xn = qx * iz, yn = qy * iz;
          const F d = V::fma(xn, xn, yn * yn) - V::load(p.rho2 + k);
          stage_radial[g] = V::select(inside, V::load(ref.intensity + k) * d, zero);
        }
      }
      for (int g = 0; g < groups; ++g) {
        const std::size_t k = bs + static_cast<std::size_t>(g) * V::kWidth;
        const F a = stage_a[g], b = stage_b[g], qz = stage_qz[g];
        const M inside = stage_inside[g];
        const Cell<F> c = V::load_cell(p.cells, stage_index + g * V::kWidth, p.width);
        const M depth_ok = inside & (c.d00 > zero) & (c.d10 > zero) & (c.d01 > zero) & (c.d11 > zero);
        const F d2 = lerp<V>(b, lerp<V>(a, c.d00, c.d10), lerp<V>(a, c.d01, c.d11));
        // Occluded in frame 2: neither residual is meaningful.
        const M occluded = depth_ok & (qz > d2 + margin);
        const M valid_i = V::and_not(inside, occluded);
        const M valid_d = V::and_not(depth_ok, occluded);
        if (kStore) V::store_flags(out.flags + k, valid_i, valid_d);
        sums.valid_i += V::count(valid_i);
        sums.valid_d += V::count(valid_d);
        // One objective's residual r (zero where invalid): stored, summed (plain and under the
        // stored weights w), and its image gradients from the cell's corners e00..e11.
        const auto objective = [&](M valid, F r, F e00, F e10, F e01, F e11, float* r_out, const float* w,
                                   float* gu_out, float* gv_out, const float* ref_gu, const float* ref_gv, F& ss,
                                   F& f) {
          r = V::select(valid, r, zero);
          if (kStore) V::store(r_out + k, r);
          ss = V::fma(r, r, ss);
          if (p.weighted_sums) f = V::fma(V::load(w + k) * r, r, f);
          if (current_gradients) {
            F gu = fx * lerp<V>(b, e10 - e00, e11 - e01);
            F gv = fy * lerp<V>(a, e01 - e00, e11 - e10);
            if (average) {
              gu = half * (gu + V::load(ref_gu + k));
              gv = half * (gv + V::load(ref_gv + k));
            }
            V::store(gu_out + k, V::select(valid, gu, zero));
            V::store(gv_out + k, V::select(valid, gv, zero));
          }
        };
        if (want_i) {
          const F i2 = lerp<V>(b, lerp<V>(a, c.i00, c.i10), lerp<V>(a, c.i01, c.i11));
          F model = V::fma(V::set(p.gain), V::load(ref.intensity + k), V::set(p.offset));
          if (radial) {
            model = V::fma(V::set(p.radial), stage_radial[g], model);
            if (kStore) V::store(out.q + k, V::select(valid_i, stage_radial[g], zero));
          }
          objective(valid_i, i2 - model, c.i00, c.i10, c.i01, c.i11, out.r_i, out.w_i, out.gi_u, out.gi_v, ref.gi_u,
                    ref.gi_v, ss_i, f_i);
        }
        if (want_d) {
          F r_d = d2 - qz;
          if (p.depth_noise_exponent != 0) r_d = r_d * depth_noise_scale<V>(V::load(ref.z + k), p.depth_noise_exponent);
          objective(valid_d, r_d, c.d00, c.d10, c.d01, c.d11, out.r_d, out.w_d, out.gd_u, out.gd_v, ref.gd_u, ref.gd_v,
                    ss_d, f_d);
        }
      }
    }
    sums.f_i += V::sum(f_i);
    sums.f_d += V::sum(f_d);
    sums.ss_i += V::sum(ss_i);
    sums.ss_d += V::sum(ss_d);
  }
  return sums;
}

template <class V>
WarpSums warp(const WarpParams& p, const ReferenceArrays& ref, const TermBuffers& out, std::size_t begin,
              std::size_t end) {
  return p.store ? warp_pass<V, true>(p, ref, out, begin, end) : warp_pass<V, false>(p, ref, out, begin, end);
}

template <class V>
ScaleSums t_scale_sums(const float* r, std::size_t begin, std::size_t end, float nu, float inv_scale2) {
  using F = typename V::F;
  const F fnu = V::set(nu), fnu1 = V::set(nu + 1.0f), inv = V::set(inv_scale2);
  ScaleSums total;
  for (std::size_t s = begin; s < end; s += kFlushTerms) {
    const std::size_t s_end = s + kFlushTerms < end ? s + kFlushTerms : end;
    F acc = V::set(0.0f), acc_slope = V::set(0.0f);
    for (std::size_t k = s; k < s_end; k += V::kWidth) {
      const F x = V::load(r + k);
      const F r2 = x * x;
      const F a = r2 * inv;
      const F t = V::sum_reciprocal(a + fnu);
      const F term = r2 * fnu1 * t;
      acc = acc + term;
      acc_slope = V::fma(term, a * t, acc_slope);
    }
    total.sum += V::sum(acc);
    total.slope += V::sum(acc_slope);
  }
  return total;
}

template <class V>
JointScaleSums joint_scale_sums(const JointScaleParams& p, const TermBuffers& buf, std::size_t begin, std::size_t end) {
  using F = typename V::F;
  using M = typename V::M;
  const F zero = V::set(0.0f), a = V::set(p.p_ii), b2 = V::set(2.0f * p.p_id), c = V::set(p.p_dd);
  const F fnu = V::set(p.nu), fnu2 = V::set(p.nu + 2.0f);
  JointScaleSums total;
  for (std::size_t s = begin; s < end; s += kFlushTerms) {
    const std::size_t s_end = s + kFlushTerms < end ? s + kFlushTerms : end;
    F m_ii = zero, m_id = zero, m_dd = zero, t40 = zero, t31 = zero, t22 = zero, t13 = zero, t04 = zero;
    for (std::size_t k = s; k < s_end; k += V::kWidth) {
      const M both = V::flag(buf.flags + k, 1) & V::flag(buf.flags + k, 2);
      total.count += V::count(both);
      // Zero outside: such a lane adds nothing to any sum (each has a factor x or y).
      const F x = V::select(both, V::load(buf.r_i + k), zero), y = V::select(both, V::load(buf.r_d + k), zero);
      const F xx = x * x, xy = x * y, yy = y * y;
      const F w = fnu2 / V::fma(a, xx, V::fma(b2, xy, V::fma(c, yy, fnu)));
      const F wxx = w * xx, wxy = w * xy, wyy = w * yy;
      m_ii = m_ii + wxx;
      m_id = m_id + wxy;
      m_dd = m_dd + wyy;
      t40 = V::fma(wxx, wxx, t40);
      t31 = V::fma(wxx, wxy, t31);
      t22 = V::fma(wxx, wyy, t22);
      t13 = V::fma(wxy, wyy, t13);
      t04 = V::fma(wyy, wyy, t04);
    }
    total.m_ii += V::sum(m_ii);
    total.m_id += V::sum(m_id);
    total.m_dd += V::sum(m_dd);
    total.t40 += V::sum(t40);
    total.t31 += V::sum(t31);
    total.t22 += V::sum(t22);
    total.t13 += V::sum(t13);
    total.t04 += V::sum(t04);
  }
  return total;
}

// One objective's weights at one lane group from its model (0 where invalid; kStored reads them).
template <class V, WeightModel::Kind kKind>
inline typename V::F lane_weight(const ObjectiveWeights& m, const float* stored, std::size_t k, typename V::M valid,
                                 typename V::F r) {
  using F = typename V::F;
  F w;
  if constexpr (kKind == WeightModel::kTDistribution) {
    w = V::set(m.numerator) / V::fma(r * r, V::set(m.inv_scale2), V::set(m.denominator));
  } else if constexpr (kKind == WeightModel::kHuber) {
    // min(1, k / |r|) as k / max(k, |r|): no division by zero
    const F a = V::select(r < V::set(0.0f), -r, r), kk = V::set(m.huber);
    w = kk / V::select(a > kk, a, kk);
  } else if constexpr (kKind == WeightModel::kStored) {
    w = V::load(stored + k);
  } else {
    w = V::set(1.0f);
  }
  return V::select(valid, w, V::set(0.0f));
}

// The weight stage at one lane group: w_I, w_D from the model (0 where invalid), written to
// the buffers unless the model is kStored, which reads them.
template <class V, WeightModel::Kind kKind>
inline void lane_weights(const WeightModel& m, ObjectiveMask objectives, const TermBuffers& buf, std::size_t k,
                         typename V::M valid_i, typename V::M valid_d, typename V::F r_i, typename V::F r_d,
                         typename V::F& w_i, typename V::F& w_d) {
  if constexpr (kKind == WeightModel::kJoint) {
    // Both residuals are loaded: the joint model is used with both objectives only.
    using F = typename V::F;
    const F q = V::fma(
        V::set(m.joint.p_ii), r_i * r_i,
        V::fma(V::set(2.0f * m.joint.p_id), r_i * r_d, V::fma(V::set(m.joint.p_dd), r_d * r_d, V::set(m.joint.nu))));
    const F w = V::set(m.joint.nu + 2.0f) / q;
    const typename V::M both = valid_i & valid_d;
    w_i = V::select(both, w, lane_weight<V, WeightModel::kTDistribution>(m.intensity, buf.w_i, k, valid_i, r_i));
    w_d = V::select(both, w, lane_weight<V, WeightModel::kTDistribution>(m.depth, buf.w_d, k, valid_d, r_d));
    V::store(buf.w_i + k, w_i);
    V::store(buf.w_d + k, w_d);
    return;
  }
  if (objectives.intensity) {
    w_i = lane_weight<V, kKind>(m.intensity, buf.w_i, k, valid_i, r_i);
    if constexpr (kKind != WeightModel::kStored) V::store(buf.w_i + k, w_i);
  }
  if (objectives.depth) {
    w_d = lane_weight<V, kKind>(m.depth, buf.w_d, k, valid_d, r_d);
    if constexpr (kKind != WeightModel::kStored) V::store(buf.w_d + k, w_d);
  }
}

template <class V, WeightModel::Kind kKind>
WeighSums weigh(const WeightModel& m, ObjectiveMask objectives, const TermBuffers& buf, std::size_t begin,
                std::size_t end) {
  using F = typename V::F;
  const F zero = V::set(0.0f);
  WeighSums sums;
  for (std::size_t s = begin; s < end; s += kFlushTerms) {
    const std::size_t s_end = s + kFlushTerms < end ? s + kFlushTerms : end;
    F f_i = zero, f_d = zero, ws_i = zero, ws_d = zero;
    for (std::size_t k = s; k < s_end; k += V::kWidth) {
      const F r_i = objectives.intensity ? V::load(buf.r_i + k) : zero;
      const F r_d = objectives.depth ? V::load(buf.r_d + k) : zero;
      F w_i = zero, w_d = zero;
      lane_weights<V, kKind>(m, objectives, buf, k, V::flag(buf.flags + k, 1), V::flag(buf.flags + k, 2), r_i, r_d, w_i,
                             w_d);
      f_i = V::fma(w_i * r_i, r_i, f_i);
      f_d = V::fma(w_d * r_d, r_d, f_d);
      ws_i = ws_i + w_i;
      ws_d = ws_d + w_d;
    }
    sums.f_i += V::sum(f_i);
    sums.f_d += V::sum(f_d);
    sums.weight_sum_i += V::sum(ws_i);
    sums.weight_sum_d += V::sum(ws_d);
  }
  return sums;
}

// Rows [R0, R1] of the packed lower triangle of sum w v v^T over the staged block
// (block[0..5] = J, block[6] = r, block[7] = w; one row of kBlockTerms floats each). Row 6
// holds b and a; a = sum (w r) r in the same order as warp()'s and weigh()'s sums.
template <class V, int R0, int R1, bool kWeightSum>
inline void gram_rows(const float (*block)[kBlockTerms], int groups, typename V::F* acc) {
  using F = typename V::F;
  constexpr int E0 = R0 * (R0 + 1) / 2, E1 = (R1 + 1) * (R1 + 2) / 2;
  F local[E1 - E0 + 1];
  for (int e = 0; e < E1 - E0; ++e) local[e] = acc[E0 + e];
  local[E1 - E0] = acc[28];
  for (int g = 0; g < groups; ++g) {
    const int o = g * V::kWidth;
    const F w = V::load(&block[7][o]);
    int e = 0;
#pragma GCC unroll 8
    for (int i = R0; i <= R1; ++i) {
      const F u = w * V::load(&block[i][o]);
#pragma GCC unroll 8
      for (int j = 0; j <= i; ++j, ++e) local[e] = V::fma(u, V::load(&block[j][o]), local[e]);
    }
    if constexpr (kWeightSum) local[E1 - E0] = local[E1 - E0] + w;
  }
  for (int e = 0; e < E1 - E0; ++e) acc[E0 + e] = local[e];
  if constexpr (kWeightSum) acc[28] = local[E1 - E0];
}

template <class V>
inline void stage_jacobian(typename V::F qx, typename V::F qy, typename V::F qz, typename V::F iz, typename V::F gu,
                           typename V::F gv, typename V::F dz, typename V::F r, typename V::F w,
                           float (*block)[kBlockTerms], int o) {
  using F = typename V::F;
  const F c0 = gu * iz, c1 = gv * iz;
  const F c2 = -(V::fma(gu, qx, gv * qy) * iz * iz) - dz;  // dz: d r / d q_z beyond the image (r_D: s)
  V::store(&block[0][o], c0);
  V::store(&block[1][o], c1);
  V::store(&block[2][o], c2);
  V::store(&block[3][o], qy * c2 - qz * c1);
  V::store(&block[4][o], qz * c0 - qx * c2);
  V::store(&block[5][o], qx * c1 - qy * c0);
  V::store(&block[6][o], r);
  V::store(&block[7][o], w);
}

template <class V>
inline void flush_gram(typename V::F* acc, GramSums& sums) {
  for (int e = 0; e < 28; ++e) {
    sums.g[e] += V::sum(acc[e]);
    acc[e] = V::set(0.0f);
  }
  sums.weight_sum += V::sum(acc[28]);
  acc[28] = V::set(0.0f);
}

template <class V, WeightModel::Kind kKind>
NormalSums normal_equations(const NormalParams& p, const WeightModel& m, const ReferenceArrays& ref,
                            const TermBuffers& buf, std::size_t begin, std::size_t end) {
  using F = typename V::F;
  using M = typename V::M;
  const LanePose<V> T(p.pose);
  const F zero = V::set(0.0f), one = V::set(1.0f);
  const bool want_i = p.objectives.intensity, want_d = p.objectives.depth;
  alignas(64) float block_i[8][kBlockTerms];
  alignas(64) float block_d[8][kBlockTerms];
  F acc_i[29], acc_d[29];
  for (int e = 0; e < 29; ++e) acc_i[e] = acc_d[e] = zero;
  NormalSums sums;
  for (std::size_t s = begin; s < end; s += kFlushTerms) {
    const std::size_t s_end = s + kFlushTerms < end ? s + kFlushTerms : end;
    for (std::size_t bs = s; bs < s_end; bs += kBlockTerms) {
      const std::size_t b_end = bs + kBlockTerms < s_end ? bs + kBlockTerms : s_end;
      const int groups = static_cast<int>((b_end - bs) / V::kWidth);
      for (int g = 0; g < groups; ++g) {
        const std::size_t k = bs + static_cast<std::size_t>(g) * V::kWidth;
        const int o = g * V::kWidth;
        const M valid_i = V::flag(buf.flags + k, 1), valid_d = V::flag(buf.flags + k, 2);
        F qx, qy, qz;
        const F z = V::load(ref.z + k);
        T.apply(V::load(ref.x + k), V::load(ref.y + k), z, qx, qy, qz);
        // 0 on terms valid in neither objective (q_z may be 0 there): J stays finite.
        const F iz = V::select(valid_i | valid_d, one / qz, zero);
        const F r_i = want_i ? V::load(buf.r_i + k) : zero;
        const F r_d = want_d ? V::load(buf.r_d + k) : zero;
        F w_i = zero, w_d = zero;
        lane_weights<V, kKind>(m, p.objectives, buf, k, valid_i, valid_d, r_i, r_d, w_i, w_d);
        if (want_i) {
          F gu = V::load(p.gi_u + k), gv = V::load(p.gi_v + k);
          if (p.radial != 0.0f) {
            // The radial term -radial I_1 rho_y^2: fx d/du = -2 radial I_1 x_n (y_n for v).
            const F s2 = V::set(-2.0f * p.radial) * V::load(ref.intensity + k) * iz;
            gu = V::fma(s2, qx, gu);
            gv = V::fma(s2, qy, gv);
          }
          stage_jacobian<V>(qx, qy, qz, iz, gu, gv, zero, r_i, w_i, block_i, o);
        }
        if (want_d) {
          F gu = V::load(p.gd_u + k), gv = V::load(p.gd_v + k), dz = one;
          if (p.depth_noise_exponent != 0) {
            // Invalid terms have r = 0 and w = 0; s is finite wherever z > 0.
            dz = V::select(valid_d, depth_noise_scale<V>(z, p.depth_noise_exponent), zero);
            gu = gu * dz;
            gv = gv * dz;
          }
          stage_jacobian<V>(qx, qy, qz, iz, gu, gv, dz, r_d, w_d, block_d, o);
        }
      }
      if (want_i) {
        gram_rows<V, 0, 3, true>(block_i, groups, acc_i);
        gram_rows<V, 4, 5, false>(block_i, groups, acc_i);
        gram_rows<V, 6, 6, false>(block_i, groups, acc_i);
      }
      if (want_d) {
        gram_rows<V, 0, 3, true>(block_d, groups, acc_d);
        gram_rows<V, 4, 5, false>(block_d, groups, acc_d);
        gram_rows<V, 6, 6, false>(block_d, groups, acc_d);
      }
    }
    flush_gram<V>(acc_i, sums.intensity);
    flush_gram<V>(acc_d, sums.depth);
  }
  return sums;
}

template <class V>
WeighSums weigh_any(const WeightModel& m, ObjectiveMask o, const TermBuffers& buf, std::size_t begin, std::size_t end) {
  switch (m.kind) {
    case WeightModel::kTDistribution:
      return weigh<V, WeightModel::kTDistribution>(m, o, buf, begin, end);
    case WeightModel::kHuber:
      return weigh<V, WeightModel::kHuber>(m, o, buf, begin, end);
    case WeightModel::kStored:
      return weigh<V, WeightModel::kStored>(m, o, buf, begin, end);
    case WeightModel::kJoint:
      return weigh<V, WeightModel::kJoint>(m, o, buf, begin, end);
    case WeightModel::kUnit:
      break;
  }
  return weigh<V, WeightModel::kUnit>(m, o, buf, begin, end);
}

template <class V>
NormalSums normal_equations_any(const NormalParams& p, const WeightModel& m, const ReferenceArrays& ref,
                                const TermBuffers& buf, std::size_t begin, std::size_t end) {
  switch (m.kind) {
    case WeightModel::kTDistribution:
      return normal_equations<V, WeightModel::kTDistribution>(p, m, ref, buf, begin, end);
    case WeightModel::kHuber:
      return normal_equations<V, WeightModel::kHuber>(p, m, ref, buf, begin, end);
    case WeightModel::kStored:
      return normal_equations<V, WeightModel::kStored>(p, m, ref, buf, begin, end);
    case WeightModel::kJoint:
      return normal_equations<V, WeightModel::kJoint>(p, m, ref, buf, begin, end);
    case WeightModel::kUnit:
      break;
  }
  return normal_equations<V, WeightModel::kUnit>(p, m, ref, buf, begin, end);
}

template <class V>
std::size_t reference_row(const ReferenceRow& row, const ReferenceOut& out, std::size_t k) {
  int u = 0;
  // Lane types that can compress (Avx512Lanes) do the whole lane groups of the row.
  if constexpr (V::kCompressesRows) u = V::reference_row_groups(row, out, k);
  for (; u < row.width; ++u) {
    const double z = row.depth[u];
    if (!(z >= row.min_depth && z <= row.max_depth)) continue;
    out.x[k] = static_cast<float>((u - row.cx) * row.ifx * z);
    out.y[k] = static_cast<float>(row.ry * z);
    out.z[k] = row.depth[u];
    out.intensity[k] = row.intensity[u];
    ++k;
  }
  return k;
}

#include "odometry/kernels/brightness_kernels_impl.h"
#include "odometry/kernels/frame_move_kernels_impl.h"

template <class V>
KernelTable make_table(KernelIsa isa) {
  return {isa,
          &reference_row<V>,
          &warp<V>,
          &t_scale_sums<V>,
          &joint_scale_sums<V>,
          &weigh_any<V>,
          &brightness_sums<V>,
          &correct_brightness<V>,
          &squared_radii<V>,
          &normal_equations_any<V>,
          &global_shutter_rows<V>,
          &retime_depth_rows<V>};
}

}  // namespace BIVO_KERNEL_NS
}  // namespace bivo::odometry
