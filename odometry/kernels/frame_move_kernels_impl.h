// The frame-move kernels (KernelTable::global_shutter_rows, retime_depth_rows; rgbd_kernels.h)
// as templates over a lane type; included by rgbd_kernels_impl.h inside its namespace
// BIVO_KERNEL_NS; no include guard on purpose. The arithmetic runs in lanes; the colour move's
// choice of each lane's second row and the depth splat's writes are per pixel.

// A product passed through `rounded` is rounded to float before it is added (the compiler
// cannot fuse the two into an FMA across the empty asm), so every instruction set computes
// what the scalar build computes, bit for bit.
inline float rounded(float a) {
  __asm__("" : "+x"(a));
  return a;
}
#if defined(__AVX2__) && defined(__FMA__)
inline Avx2F rounded(Avx2F a) {
  __asm__("" : "+x"(a.v));
  return a;
}
#endif
#if defined(__AVX512F__)
inline Avx512F rounded(Avx512F a) {
  __asm__("" : "+v"(a.v));
  return a;
}
#endif

// q = R P + t and its projection for the row pose at `rp` (12 floats), in the order of
// Eigen's 3x3 product: (R_i0 P_0 + (R_i1 P_1 + R_i2 P_2)) + t_i.
template <class V>
struct RowProjection {
  typename V::F qz, x, y;
};

template <class V>
RowProjection<V> project_with_row(const typename V::F* r, typename V::F px, typename V::F py, typename V::F pz,
                                  typename V::F fx, typename V::F fy, typename V::F cx, typename V::F cy) {
  using F = typename V::F;
  const F qx = (rounded(r[0] * px) + (rounded(r[1] * py) + rounded(r[2] * pz))) + r[9];
  const F qy = (rounded(r[3] * px) + (rounded(r[4] * py) + rounded(r[5] * pz))) + r[10];
  const F qz = (rounded(r[6] * px) + (rounded(r[7] * py) + rounded(r[8] * pz))) + r[11];
  return {qz, fx * qx / qz + cx, fy * qy / qz + cy};
}

template <class V>
void global_shutter_rows(const GlobalShutterParams& p, int v_begin, int v_end) {
  using F = typename V::F;
  using M = typename V::M;
  constexpr int W = V::kWidth;
  const int w = p.width, h = p.height;
  const F fx = V::set(p.fx), fy = V::set(p.fy), cx = V::set(p.cx), cy = V::set(p.cy);
  const F zero = V::set(0.0f), one = V::set(1.0f), half = V::set(0.5f);
  const F right = V::set(static_cast<float>(w - 1)), bottom = V::set(static_cast<float>(h - 1));
  const auto in_image = [&](const RowProjection<V>& at) {
    return (at.qz > zero) & (at.x >= zero) & (at.y >= zero) & (at.x <= right) & (at.y <= bottom);
  };
  for (int v = v_begin; v < v_end; ++v) {
    const float ray_y = (static_cast<float>(v) - p.cy) / p.fy;
    const F ry = V::set(ray_y);
    F own[12];
    for (int i = 0; i < 12; ++i) own[i] = V::set(p.pose[12 * v + i]);
    const float* depth_row = p.depth + static_cast<std::ptrdiff_t>(v) * w;
    float* out_row = p.out + static_cast<std::ptrdiff_t>(v) * w;
    float z_last = 0.0f;
    for (int u = 0; u < w; ++u) {
      const float d = depth_row[u];
      if (d > 0.0f) {
        z_last = d;
      } else if (z_last == 0.0f) {
        z_last = p.fallback;
      }
      p.row_depth[u] = z_last;
    }
    for (int u = w; u < w + W; ++u) p.row_depth[u] = 0.0f;
    for (int u0 = 0; u0 < w; u0 += W) {
      const int lanes = w - u0 < W ? w - u0 : W;
      const F z = V::load(p.row_depth + u0);
      const F px = z * (V::load(p.columns + u0) - cx) / fx, py = z * ry;
      const RowProjection<V> first = project_with_row<V>(own, px, py, z, fx, fy, cx, cy);
      const M inside_first = (z > zero) & in_image(first);
      if (V::count(inside_first) == 0) continue;
      // Each lane's second row: the row its point landed on (its own where the first pass
      // failed: the lane is dropped below).
      float keep[W];
      std::int32_t row[W];
      V::store(keep, V::select(inside_first, one, zero));
      V::truncate(V::select(inside_first, first.y + half, V::set(static_cast<float>(v))), row);
      bool one_row = true;
      for (int j = 0; j < W; ++j) one_row = one_row && row[j] == row[0];
      F second_pose[12];
      if (one_row) {  // the usual case: the lanes' points were all read by one row
        for (int i = 0; i < 12; ++i) second_pose[i] = V::set(p.pose[12 * row[0] + i]);
      } else {
        float rows[12][W];
        for (int j = 0; j < W; ++j) {
          for (int i = 0; i < 12; ++i) rows[i][j] = p.pose[12 * row[j] + i];
        }
        for (int i = 0; i < 12; ++i) second_pose[i] = V::load(rows[i]);
      }
      const RowProjection<V> second = project_with_row<V>(second_pose, px, py, z, fx, fy, cx, cy);
      const M inside = inside_first & in_image(second);
      if (V::count(inside) == 0) continue;
      // The bilinear cell of each lane (cell 0 where the lane is dropped).
      std::int32_t xi[W], yi[W], cell[W];
      float cell_x[W], cell_y[W];
      V::store(keep, V::select(inside, one, zero));
      V::truncate(V::select(inside, second.x, zero), xi);  // no NaN or out-of-range lane converted
      V::truncate(V::select(inside, second.y, zero), yi);
      for (int j = 0; j < W; ++j) {
        const bool used = keep[j] != 0.0f;
        const std::int32_t x0 = used ? (xi[j] < w - 2 ? xi[j] : w - 2) : 0;
        const std::int32_t y0 = used ? (yi[j] < h - 2 ? yi[j] : h - 2) : 0;
        cell[j] = y0 * w + x0;
        cell_x[j] = static_cast<float>(x0);
        cell_y[j] = static_cast<float>(y0);
      }
      const F ax = second.x - V::load(cell_x), ay = second.y - V::load(cell_y);
      const F top = rounded((one - ax) * V::gather(p.intensity, cell)) + rounded(ax * V::gather(p.intensity + 1, cell));
      const F low =
          rounded((one - ax) * V::gather(p.intensity + w, cell)) + rounded(ax * V::gather(p.intensity + w + 1, cell));
      const F value = rounded((one - ay) * top) + rounded(ay * low);
      float moved[W];
      V::store(moved, value);
      for (int j = 0; j < lanes; ++j) {
        if (keep[j] != 0.0f) out_row[u0 + j] = moved[j];
      }
    }
  }
}

// Depth change per pixel through z from its neighbours a and b (central difference), 0 unless
// both are valid and within 5 % of z (one surface).
template <class V>
typename V::F depth_slope(typename V::F a, typename V::F z, typename V::F b) {
  using F = typename V::F;
  const F zero = V::set(0.0f), tolerance = V::set(0.05f) * z;
  const F da = a - z, db = b - z;
  const auto small = [&](F d) { return (d < tolerance) & (-d < tolerance); };  // |d| < tolerance
  return V::select((a > zero) & (b > zero) & small(da) & small(db), V::set(0.5f) * (b - a), zero);
}

template <class V>
void retime_depth_rows(const RetimeDepthParams& p, int v_begin, int v_end) {
  using F = typename V::F;
  using M = typename V::M;
  constexpr int W = V::kWidth;
  const int w = p.width, h = p.height;
  const float* r = p.pose;
  const F r00 = V::set(r[0]), r10 = V::set(r[3]), r20 = V::set(r[6]);
  const F tx = V::set(r[9]), ty = V::set(r[10]), tz = V::set(r[11]);
  const F fx = V::set(p.fx), fy = V::set(p.fy), cx = V::set(p.cx), cy = V::set(p.cy);
  const F zero = V::set(0.0f), half = V::set(0.5f), one = V::set(1.0f);
  const F low = V::set(-0.5f), right = V::set(static_cast<float>(w) - 0.5f),
          bottom = V::set(static_cast<float>(h) - 0.5f);
  float* row = p.row + 1;  // row[-1] and row[w..] are 0: no slope across the image's edge
  for (int u = -1; u < w + 1 + W; ++u) row[u] = 0.0f;
  for (int v = v_begin; v < v_end; ++v) {
    // q = z R [ray_x, ray_y, 1] + t, the row's part of R [., ray_y, 1] once per row
    const float ray_y = (static_cast<float>(v) - p.cy) / p.fy;
    const F bx = V::set(rounded(r[1] * ray_y) + r[2]), by = V::set(rounded(r[4] * ray_y) + r[5]);
    const F bz = V::set(rounded(r[7] * ray_y) + r[8]);
    const float* depth_row = p.depth + static_cast<std::ptrdiff_t>(v) * w;
    for (int u = 0; u < w; ++u) row[u] = depth_row[u];
    // Rows above and below (none at the image's edge: no vertical slope there).
    const float* up = v > 0 ? depth_row - w : nullptr;
    const float* down = v + 1 < h ? depth_row + w : nullptr;
    for (int u0 = 0; u0 < w; u0 += W) {
      const F z = V::load(row + u0), rx = V::load(p.rays + u0);
      const F qz = rounded(z * (rounded(r20 * rx) + bz)) + tz;
      M keep = (z > zero) & (qz > zero) & V::lanes_below(static_cast<std::size_t>(u0), static_cast<std::size_t>(w));
      if (V::count(keep) == 0) continue;
      const F inv_z = one / qz;
      const F x = rounded(fx * (rounded(z * (rounded(r00 * rx) + bx)) + tx) * inv_z) + cx;
      const F y = rounded(fy * (rounded(z * (rounded(r10 * rx) + by)) + ty) * inv_z) + cy;
      keep = keep & (x > low) & (x < right) & (y > low) & (y < bottom);
      if (V::count(keep) == 0) continue;
      // The nearest pixel, and the surface's depth at its centre along the image's slope.
      std::int32_t xi[W], yi[W];
      V::truncate(V::select(keep, x + half, zero), xi);
      V::truncate(V::select(keep, y + half, zero), yi);
      float pixel_x[W], pixel_y[W];
      for (int j = 0; j < W; ++j) {
        pixel_x[j] = static_cast<float>(xi[j]);
        pixel_y[j] = static_cast<float>(yi[j]);
      }
      const F gx = depth_slope<V>(V::load(row + u0 - 1), z, V::load(row + u0 + 1));
      F gy = zero;
      if (up && down) {
        float above[W], below[W];
        for (int j = 0; j < W; ++j) {
          const bool in_row = u0 + j < w;
          above[j] = in_row ? up[u0 + j] : 0.0f;
          below[j] = in_row ? down[u0 + j] : 0.0f;
        }
        gy = depth_slope<V>(V::load(above), z, V::load(below));
      }
      const F at_centre = (qz + rounded(gx * (V::load(pixel_x) - x))) + rounded(gy * (V::load(pixel_y) - y));
      float value[W], kept[W];
      V::store(value, at_centre);
      V::store(kept, V::select(keep, one, zero));
      for (int j = 0; j < W; ++j) {
        if (kept[j] == 0.0f) continue;
        float& slot = p.out[static_cast<std::ptrdiff_t>(yi[j]) * w + xi[j]];
        slot = value[j] < slot ? value[j] : slot;
      }
    }
  }
}
