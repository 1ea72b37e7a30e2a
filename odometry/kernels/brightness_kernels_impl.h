// The brightness kernels (KernelTable::brightness_sums, correct_brightness, squared_radii) as templates over
// a lane type; included by rgbd_kernels_impl.h inside its namespace BIVO_KERNEL_NS; no
// include guard on purpose. x = I_1 - kBrightnessCentre; invalid r_I (and q) lanes are 0, r_I stays 0.

template <class V>
BrightnessSums brightness_sums(const BrightnessFit& p, const TermBuffers& buf, std::size_t begin, std::size_t end) {
  using F = typename V::F;
  using M = typename V::M;
  const F zero = V::set(0.0f), one = V::set(1.0f), centre = V::set(kBrightnessCentre);
  BrightnessSums total;
  for (std::size_t s = begin; s < end; s += kFlushTerms) {
    const std::size_t s_end = s + kFlushTerms < end ? s + kFlushTerms : end;
    F sw = zero, swx = zero, swxx = zero, swr = zero, swxr = zero;
    F swq = zero, swxq = zero, swqq = zero, swqr = zero;
    for (std::size_t k = s; k < s_end; k += V::kWidth) {
      const M valid = V::flag(buf.flags + k, 1);
      const F w = V::select(valid, p.weighted ? V::load(buf.w_i + k) : one, zero);
      const F x = V::load(p.intensity + k) - centre, r = V::load(buf.r_i + k);
      const F wx = w * x;
      sw = sw + w;
      swx = swx + wx;
      swxx = V::fma(wx, x, swxx);
      swr = V::fma(w, r, swr);
      swxr = V::fma(wx, r, swxr);
      if (p.radial) {
        const F q = V::load(buf.q + k);  // 0 where r_I is invalid
        const F wq = w * q;
        swq = swq + wq;
        swxq = V::fma(wx, q, swxq);
        swqq = V::fma(wq, q, swqq);
        swqr = V::fma(wq, r, swqr);
      }
    }
    total.w += V::sum(sw);
    total.wx += V::sum(swx);
    total.wxx += V::sum(swxx);
    total.wr += V::sum(swr);
    total.wxr += V::sum(swxr);
    total.wq += V::sum(swq);
    total.wxq += V::sum(swxq);
    total.wqq += V::sum(swqq);
    total.wqr += V::sum(swqr);
  }
  return total;
}

template <class V>
double correct_brightness(const BrightnessFit& p, const BrightnessStep& step, const TermBuffers& buf, std::size_t begin,
                          std::size_t end) {
  using F = typename V::F;
  using M = typename V::M;
  const F g = V::set(step.gain), o = V::set(step.offset), c = V::set(step.radial);
  const bool radial = p.radial && step.radial != 0.0f;
  double ss = 0.0;
  for (std::size_t s = begin; s < end; s += kFlushTerms) {
    const std::size_t s_end = s + kFlushTerms < end ? s + kFlushTerms : end;
    F acc = V::set(0.0f);
    for (std::size_t k = s; k < s_end; k += V::kWidth) {
      const M valid = V::flag(buf.flags + k, 1);
      const F r0 = V::load(buf.r_i + k);
      F model = V::fma(g, V::load(p.intensity + k), o);
      if (radial) model = V::fma(c, V::load(buf.q + k), model);
      const F r = V::select(valid, r0 - model, r0);
      V::store(buf.r_i + k, r);
      acc = V::fma(r, r, acc);
    }
    ss += V::sum(acc);
  }
  return ss;
}

template <class V>
void squared_radii(const ReferenceArrays& ref, float* rho2, std::size_t begin, std::size_t end) {
  using F = typename V::F;
  const F one = V::set(1.0f);
  for (std::size_t k = begin; k < end; k += V::kWidth) {
    const F iz = one / V::load(ref.z + k);  // as warp forms x_n, y_n of q = p at the identity
    const F xn = V::load(ref.x + k) * iz, yn = V::load(ref.y + k) * iz;
    V::store(rho2 + k, V::fma(xn, xn, yn * yn));
  }
}
