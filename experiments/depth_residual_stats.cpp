#include "experiments/depth_residual_stats.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <sstream>

#include "odometry/io/lens_distortion.h"
#include "odometry/io/pose_error.h"
#include "odometry/io/tum_dataset.h"
#include "solvers/error.h"

namespace bivo::experiments {

namespace {

constexpr double kOutlierRel = 0.10;
constexpr int kLags[] = {1, 2, 4, 8, 16, 32, 64, 128};
constexpr int kColourStride = 4;     // every 4th pixel and row is a colour term
constexpr double kFlatColour = 4.0;  // gray levels per pixel: a flat neighbourhood
constexpr double kDark = 8.0, kSaturated = 247.0;

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

double robust_spread(const std::vector<double>& v) {
  const double m = median(v);
  std::vector<double> dev(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) dev[i] = std::fabs(v[i] - m);
  return 1.4826 * median(dev);
}

// Depth of `d` at (x, y): bilinear where the 4 neighbours are valid and within 5 % of each
// other, else the nearest pixel's; 0 when missing.
double sample_depth(const std::vector<float>& d, int w, int h, double x, double y) {
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  if (x0 < 0 || y0 < 0 || x0 + 1 >= w || y0 + 1 >= h) return 0.0;
  const float a = d[y0 * w + x0], b = d[y0 * w + x0 + 1], c = d[(y0 + 1) * w + x0], e = d[(y0 + 1) * w + x0 + 1];
  const float lo = std::min({a, b, c, e}), hi = std::max({a, b, c, e});
  if (lo > 0 && hi - lo < 0.05f * lo) {
    const double fx = x - x0, fy = y - y0;
    return (1 - fy) * ((1 - fx) * a + fx * b) + fy * ((1 - fx) * c + fx * e);
  }
  const int xn = static_cast<int>(std::lround(x)), yn = static_cast<int>(std::lround(y));
  return d[yn * w + xn];
}

// One colour comparison at a correspondence: y = ln I_j(x') - ln I_i(x), rho^2 at x and x'.
struct ColourTerm {
  float y, rho2_i, rho2_j;
  int pair;
};

// k of ln(1 - k rho_j^2) - ln(1 - k rho_i^2) + c_pair fit to the terms' y: Gauss-Newton on k with
// the pair offsets eliminated (weighted means per pair), Huber weights (1.345 sigma, sigma the
// MAD of the centred residual) re-estimated at every step. NaN when k is not observed (no term
// moves in rho^2) or the fit leaves the model's domain (k in (-1, 1)).
double fit_colour_falloff(const std::vector<ColourTerm>& terms, int pairs) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (terms.empty() || pairs < 1) return nan;
  const std::size_t n = terms.size();
  std::vector<double> w(n, 1.0), e(n), J(n), centred(n);
  double k = 0.0;
  for (int it = 0; it < 50; ++it) {
    std::vector<double> sw(static_cast<std::size_t>(pairs), 0.0), se(sw), sj(sw);
    for (std::size_t i = 0; i < n; ++i) {
      const ColourTerm& t = terms[i];
      const double vi = 1.0 - k * t.rho2_i, vj = 1.0 - k * t.rho2_j;
      e[i] = t.y - (std::log(vj) - std::log(vi));
      J[i] = -t.rho2_j / vj + t.rho2_i / vi;
      sw[t.pair] += w[i];
      se[t.pair] += w[i] * e[i];
      sj[t.pair] += w[i] * J[i];
    }
    double num = 0.0, den = 0.0, wsum = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t p = static_cast<std::size_t>(terms[i].pair);
      centred[i] = e[i] - se[p] / sw[p];
      const double jc = J[i] - sj[p] / sw[p];
      num += w[i] * jc * centred[i];
      den += w[i] * jc * jc;
      wsum += w[i];
    }
    if (!(den > 1e-9 * wsum)) return nan;
    const double step = num / den;
    k += step;
    if (!(std::fabs(k) < 1.0)) return nan;
    std::vector<double> dev(n);
    for (std::size_t i = 0; i < n; ++i) dev[i] = std::fabs(centred[i]);
    const double c = 1.345 * std::max(1e-6, 1.4826 * median(dev));
    for (std::size_t i = 0; i < n; ++i) w[i] = dev[i] <= c ? 1.0 : c / dev[i];
    if (std::fabs(step) < 1e-6) break;
  }
  return k;
}

// Bilinear intensity of `im` at (x, y); NaN outside the image.
double sample_intensity(const std::vector<float>& im, int w, int h, double x, double y) {
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  if (x0 < 0 || y0 < 0 || x0 + 1 >= w || y0 + 1 >= h) return std::numeric_limits<double>::quiet_NaN();
  const double fx = x - x0, fy = y - y0;
  const auto at = [&](int u, int v) { return static_cast<double>(im[static_cast<std::size_t>(v) * w + u]); };
  return (1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x0 + 1, y0)) +
         fy * ((1 - fx) * at(x0, y0 + 1) + fx * at(x0 + 1, y0 + 1));
}

}  // namespace

DepthResidualStats depth_residual_stats(const std::string& dir, const DepthResidualOptions& o) {
  namespace io = odometry::io;
  if (o.gap < 1 || o.max_pairs < 1) {
    throw Error("depth-stats: gap " + std::to_string(o.gap) + " and pairs " + std::to_string(o.max_pairs) +
                " must be >= 1");
  }
  io::SequenceOptions so;
  so.max_frames = o.max_frames;
  const io::TumSequence seq = io::open_tum_sequence(dir, so);
  if (!seq.groundtruth) throw Error("depth-stats: '" + dir + "' has no groundtruth.txt");
  const int n = static_cast<int>(seq.frames.size());
  if (n <= o.gap) {
    throw Error("depth-stats: '" + dir + "' has " + std::to_string(n) + " frames, too few for gap " +
                std::to_string(o.gap));
  }
  const int candidates = n - o.gap;
  const int pairs = std::min(o.max_pairs, candidates);
  const io::Intrinsics K = seq.intrinsics;

  DepthResidualStats s;
  s.sequence = std::filesystem::path(dir).filename().string();
  std::vector<double> rel, over_z2, depth;
  std::vector<double> rel_inner, rel_outer;
  double lag_num[std::size(kLags)] = {}, lag_a[std::size(kLags)] = {}, lag_b[std::size(kLags)] = {};
  std::vector<std::pair<double, double>> by_depth;  // (z, r)
  std::vector<double> pair_means;
  std::vector<ColourTerm> colour;
  std::size_t compared = 0, outliers = 0;
  for (int p = 0; p < pairs; ++p) {
    const int i =
        pairs == 1 ? 0 : static_cast<int>(std::lround(static_cast<double>(p) * (candidates - 1) / (pairs - 1)));
    const int j = i + o.gap;
    io::RgbdImage a = io::load_rgbd_image(seq.frames[i]), b = io::load_rgbd_image(seq.frames[j]);
    if (!seq.distortion.is_identity()) {
      const io::Undistortion u(K, seq.distortion, a.width, a.height);
      u.apply(a);
      u.apply(b);
    }
    const auto T = io::groundtruth_motion(*seq.groundtruth, a.timestamp, b.timestamp);
    if (!T) continue;
    ++s.pairs;
    const int w = a.width, h = a.height;
    const double cx = K.cx, cy = K.cy;
    const double r2max =
        std::max(cx, w - 1 - cx) * std::max(cx, w - 1 - cx) + std::max(cy, h - 1 - cy) * std::max(cy, h - 1 - cy);
    std::vector<float> e(static_cast<std::size_t>(w) * h, std::nanf(""));
    double pair_sum = 0;
    std::size_t pair_n = 0;
    for (int v = 0; v < h; ++v) {
      for (int u = 0; u < w; ++u) {
        const double z = a.depth[v * w + u];
        if (!(z > 0)) continue;
        const Eigen::Vector3d X((u - cx) / K.fx * z, (v - cy) / K.fy * z, z);
        const Eigen::Vector3d Y = *T * X;
        if (!(Y.z() > 0.1)) continue;
        const double xb = K.fx * Y.x() / Y.z() + cx, yb = K.fy * Y.y() / Y.z() + cy;
        const double zb = sample_depth(b.depth, w, h, xb, yb);
        if (!(zb > 0)) continue;
        ++compared;
        const double r = zb - Y.z();
        if (std::fabs(r) > kOutlierRel * Y.z()) {
          ++outliers;
          continue;
        }
        const double q = r / Y.z();
        rel.push_back(q);
        over_z2.push_back(r / (Y.z() * Y.z()));
        depth.push_back(Y.z());
        by_depth.emplace_back(Y.z(), r);
        const double rho2 = ((u - cx) * (u - cx) + (v - cy) * (v - cy)) / r2max;
        if (rho2 < 0.1) rel_inner.push_back(q);
        if (rho2 > 0.5) rel_outer.push_back(q);
        if (u % kColourStride == 0 && v % kColourStride == 0 && u > 0 && v > 0 && u + 1 < w && v + 1 < h) {
          const auto I = [&](int x, int y) { return static_cast<double>(a.intensity[y * w + x]); };
          const double flat = 0.5 * (std::fabs(I(u + 1, v) - I(u - 1, v)) + std::fabs(I(u, v + 1) - I(u, v - 1)));
          const double ia = I(u, v), ib = sample_intensity(b.intensity, w, h, xb, yb);
          if (flat < kFlatColour && ia > kDark && ia < kSaturated && ib > kDark && ib < kSaturated) {
            const double rho2b = ((xb - cx) * (xb - cx) + (yb - cy) * (yb - cy)) / r2max;
            colour.push_back({static_cast<float>(std::log(ib) - std::log(ia)), static_cast<float>(rho2),
                              static_cast<float>(rho2b), s.pairs - 1});
          }
        }
        e[v * w + u] = static_cast<float>(q);
        pair_sum += q;
        ++pair_n;
      }
    }
    if (pair_n == 0) continue;
    const double pm = pair_sum / pair_n;
    pair_means.push_back(pm);
    // Autocorrelation of the pair's residual image (its mean removed) along rows and columns.
    for (std::size_t k = 0; k < std::size(kLags); ++k) {
      const int L = kLags[k];
      for (int v = 0; v < h; ++v) {
        for (int u = 0; u < w; ++u) {
          const float x = e[v * w + u];
          if (std::isnan(x)) continue;
          for (const int idx : {u + L < w ? v * w + u + L : -1, v + L < h ? (v + L) * w + u : -1}) {
            if (idx < 0 || std::isnan(e[idx])) continue;
            const double p0 = x - pm, p1 = e[idx] - pm;
            lag_num[k] += p0 * p1;
            lag_a[k] += p0 * p0;
            lag_b[k] += p1 * p1;
          }
        }
      }
    }
  }
  if (rel.empty()) throw Error("depth-stats: no pixel of '" + dir + "' could be compared");
  s.outlier_share = compared ? static_cast<double>(outliers) / compared : 0.0;
  s.median_depth_m = median(depth);
  s.beyond_3m =
      static_cast<double>(std::count_if(depth.begin(), depth.end(), [](double z) { return z > 3.0; })) / depth.size();
  double sum = 0;
  for (double q : rel) sum += q;
  s.mean_rel = sum / rel.size();
  s.spread_z2 = robust_spread(over_z2);
  // Correlation length: log-linear interpolation of the lag where C crosses 1/e.
  double prev_c = 1.0, prev_l = 0.0;
  s.correlation_px = kLags[std::size(kLags) - 1];
  for (std::size_t k = 0; k < std::size(kLags); ++k) {
    const double c = lag_num[k] / std::sqrt(std::max(1e-300, lag_a[k] * lag_b[k]));
    if (c < std::exp(-1.0)) {
      const double f = (prev_c - std::exp(-1.0)) / std::max(1e-12, prev_c - c);
      s.correlation_px = prev_l + f * (kLags[k] - prev_l);
      break;
    }
    prev_c = c;
    prev_l = kLags[k];
  }
  const auto rms = [](const std::vector<double>& v) {
    double q = 0;
    for (double x : v) q += x * x;
    return v.empty() ? 0.0 : std::sqrt(q / v.size());
  };
  s.radial_ratio = rms(rel_inner) > 0 ? rms(rel_outer) / rms(rel_inner) : 0.0;
  s.pair_bias_rms = rms(pair_means);
  s.colour_falloff = fit_colour_falloff(colour, s.pairs);
  // spread(r) per depth bin, then the least-squares slope of log spread against log z.
  const double edges[] = {0.5, 0.8, 1.1, 1.5, 2.0, 2.6, 3.3, 4.2, 6.0, 10.0};
  std::vector<double> lx, ly;
  for (std::size_t k = 0; k + 1 < std::size(edges); ++k) {
    std::vector<double> r, zs;
    for (const auto& [z, res] : by_depth) {
      if (z >= edges[k] && z < edges[k + 1]) {
        r.push_back(res);
        zs.push_back(z);
      }
    }
    if (r.size() < 2000) continue;
    lx.push_back(std::log(median(zs)));
    ly.push_back(std::log(robust_spread(r)));
  }
  if (lx.size() >= 2) {
    double mx = 0, my = 0;
    for (std::size_t k = 0; k < lx.size(); ++k) mx += lx[k], my += ly[k];
    mx /= lx.size();
    my /= ly.size();
    double sxy = 0, sxx = 0;
    for (std::size_t k = 0; k < lx.size(); ++k) sxy += (lx[k] - mx) * (ly[k] - my), sxx += (lx[k] - mx) * (lx[k] - mx);
    s.depth_exponent = sxx > 0 ? sxy / sxx : 0.0;
  }
  return s;
}

std::string depth_residual_table(const std::vector<DepthResidualStats>& rows) {
  std::ostringstream t;
  t << "| sequence | pairs | median z [m] | z > 3 m | outliers | mean r/z [%] | pair-mean RMS [%] | "
       "spread r/z^2 [1e-3/m] | corr. length [px] | edge/centre RMS | depth exponent | colour fall-off k |\n"
       "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  t << std::fixed;
  for (const DepthResidualStats& s : rows) {
    t << "| " << s.sequence << " | " << s.pairs << " | " << std::setprecision(2) << s.median_depth_m << " | "
      << std::setprecision(0) << 100 * s.beyond_3m << " % | " << std::setprecision(1) << 100 * s.outlier_share
      << " % | " << std::setprecision(2) << 100 * s.mean_rel << " | " << 100 * s.pair_bias_rms << " | "
      << 1e3 * s.spread_z2 << " | " << std::setprecision(1) << s.correlation_px << " | " << std::setprecision(2)
      << s.radial_ratio << " | " << s.depth_exponent << " | ";
    if (std::isnan(s.colour_falloff))
      t << "- |\n";
    else
      t << s.colour_falloff << " |\n";
  }
  return t.str();
}

}  // namespace bivo::experiments
