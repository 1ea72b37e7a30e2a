#include "odometry/rgbd_problem.h"

#include <cmath>
#include <sstream>

#include "solvers/error.h"
#include "solvers/se3.h"

namespace bivo::odometry {
namespace {

namespace se3 = solvers::se3;

// Everything one term needs at one pose, in double: the Jacobians must match finite
// differences to 1e-4, which float projection (u ~ 300, ulp ~ 3e-5 px) cannot deliver.
struct TermWarp {
  double r_i = 0.0, r_d = 0.0;
  double qx = 0.0, qy = 0.0, qz = 0.0;
  double gi_u = 0.0, gi_v = 0.0;  // fx dI_2/du, fy dI_2/dv at y
  double gd_u = 0.0, gd_v = 0.0;  // fx dD_2/du, fy dD_2/dv at y
  unsigned char flags = 0;        // 1: r_I valid, 2: r_D valid
};

struct WarpContext {
  double R[9], t[3];
  double fx, fy, cx, cy;
  int width, height;
  const float* intensity;
  const float* depth;
  double occlusion_margin;
  double min_z;

  WarpContext(const Eigen::Isometry3d& T, const RgbdLevel& current, double margin) {
    const Eigen::Matrix3d Rm = T.linear();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) R[3 * r + c] = Rm(r, c);
      t[r] = T.translation()(r);
    }
    fx = current.K.fx;
    fy = current.K.fy;
    cx = current.K.cx;
    cy = current.K.cy;
    width = current.intensity.width;
    height = current.intensity.height;
    intensity = current.intensity.data.data();
    depth = current.depth.data.data();
    occlusion_margin = margin;
    min_z = 1e-6;
  }

  // Warp one reference point; bilinear interpolation of I_2 and D_2 with exact derivatives
  // (within the pixel cell containing y; the interpolant is continuous, its derivative jumps
  // across cell borders).
  inline void warp(double px, double py, double pz, double i1, TermWarp& o) const {
    o.flags = 0;
    const double X = R[0] * px + R[1] * py + R[2] * pz + t[0];
    const double Y = R[3] * px + R[4] * py + R[5] * pz + t[1];
    const double Z = R[6] * px + R[7] * py + R[8] * pz + t[2];
    o.qx = X;
    o.qy = Y;
    o.qz = Z;
    if (!(Z > min_z)) return;
    const double iz = 1.0 / Z;
    const double u = fx * X * iz + cx;
    const double v = fy * Y * iz + cy;
    if (!(u >= 0.0 && v >= 0.0 && u < width - 1 && v < height - 1)) return;
    const int x0 = static_cast<int>(u), y0 = static_cast<int>(v);
    const double a = u - x0, b = v - y0;
    const std::size_t k = static_cast<std::size_t>(y0) * width + x0;
    const double i00 = intensity[k], i10 = intensity[k + 1];
    const double i01 = intensity[k + width], i11 = intensity[k + width + 1];
    const double d00 = depth[k], d10 = depth[k + 1];
    const double d01 = depth[k + width], d11 = depth[k + width + 1];
    const bool depth_ok = d00 > 0.0 && d10 > 0.0 && d01 > 0.0 && d11 > 0.0;
    if (depth_ok) {
      const double d2 = (1 - b) * ((1 - a) * d00 + a * d10) + b * ((1 - a) * d01 + a * d11);
      if (Z > d2 + occlusion_margin) return;  // occluded in frame 2: neither residual is meaningful
      o.r_d = d2 - Z;
      o.gd_u = fx * ((1 - b) * (d10 - d00) + b * (d11 - d01));
      o.gd_v = fy * ((1 - a) * (d01 - d00) + a * (d11 - d10));
      o.flags |= 2;
    }
    const double i2 = (1 - b) * ((1 - a) * i00 + a * i10) + b * ((1 - a) * i01 + a * i11);
    o.r_i = i2 - i1;
    o.gi_u = fx * ((1 - b) * (i10 - i00) + b * (i11 - i01));
    o.gi_v = fy * ((1 - a) * (i01 - i00) + a * (i11 - i10));
    o.flags |= 1;
  }
};

// Jacobian row J = [c, q x c] of a residual whose image-space gradient (times focal
// lengths) is (gu, gv); minus_z subtracts d[q]_z/dq = e_z (the r_D term).
inline void jacobian_row(double qx, double qy, double qz, double gu, double gv, bool minus_z, double J[6]) {
  const double iz = 1.0 / qz;
  const double c0 = gu * iz, c1 = gv * iz;
  double c2 = -(gu * qx + gv * qy) * iz * iz;
  if (minus_z) c2 -= 1.0;
  J[0] = c0;
  J[1] = c1;
  J[2] = c2;
  J[3] = qy * c2 - qz * c1;
  J[4] = qz * c0 - qx * c2;
  J[5] = qx * c1 - qy * c0;
}

// Running sums of one objective's quadratic model a = sum w r^2, b = sum w r J,
// H = sum w J J^T (a in double, term by term). Terms are gathered as columns sqrt(w) J into a float block and folded in
// with one vectorized 6 x B times B x 6 product per block (instead of 27 scalar
// multiply-adds per term); block sums are accumulated in double.
struct ModelAccumulator {
  static constexpr int kBlock = 512;
  Eigen::Matrix<float, 6, kBlock> J;
  Eigen::Matrix<float, kBlock, 1> r;
  int fill = 0;
  double a = 0.0;
  Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();

  inline void add(const double Jrow[6], double residual, double w) {
    a += w * residual * residual;  // in double: a must equal evaluate() at the same x
    const double s = std::sqrt(w);
    float* col = J.col(fill).data();
    for (int i = 0; i < 6; ++i) col[i] = static_cast<float>(s * Jrow[i]);
    r(fill) = static_cast<float>(s * residual);
    if (++fill == kBlock) flush();
  }
  void flush() {
    if (fill == 0) return;
    const auto Jb = J.leftCols(fill);
    const auto rb = r.head(fill);
    Eigen::Matrix<float, 6, 6> h = Eigen::Matrix<float, 6, 6>::Zero();
    h.selfadjointView<Eigen::Lower>().rankUpdate(Jb);
    H += h.selfadjointView<Eigen::Lower>().toDenseMatrix().cast<double>();
    b += (Jb * rb).cast<double>();
    fill = 0;
  }
  solvers::QuadraticModel model() {
    flush();
    solvers::QuadraticModel m;
    m.a = a;
    m.b = b;
    m.H = H;
    return m;
  }
};

}  // namespace

RgbdOdometryProblem::RgbdOdometryProblem(const RgbdLevel& reference, const RgbdLevel& current,
                                         RgbdProblemOptions options)
    : reference_(&reference), current_(&current), options_(options) {
  const auto& ri = reference.intensity;
  const auto& rd = reference.depth;
  const auto& ci = current.intensity;
  const auto& cd = current.depth;
  if (ri.width != rd.width || ri.height != rd.height || ci.width != cd.width || ci.height != cd.height ||
      ri.width != ci.width || ri.height != ci.height) {
    std::ostringstream s;
    s << "RGB-D problem: level " << reference.level << " sizes differ (reference " << ri.width << "x" << ri.height
      << " / depth " << rd.width << "x" << rd.height << ", current " << ci.width << "x" << ci.height << " / depth "
      << cd.width << "x" << cd.height << ")";
    throw Error(s.str());
  }
  if (ri.width < 2 || ri.height < 2) {
    throw Error("RGB-D problem: level " + std::to_string(reference.level) + " is too small (" +
                std::to_string(ri.width) + "x" + std::to_string(ri.height) + ")");
  }
  if (!(options_.min_depth > 0.0) || !(options_.max_depth > options_.min_depth)) {
    throw Error("RGB-D problem: depth range [" + std::to_string(options_.min_depth) + ", " +
                std::to_string(options_.max_depth) + "] is empty or not positive");
  }
  // Back-project the reference once per (pair, level): the per-iteration loop then only
  // transforms, projects and interpolates.
  const io::Intrinsics& K = reference.K;
  const double ifx = 1.0 / K.fx, ify = 1.0 / K.fy;
  const std::size_t reserve = static_cast<std::size_t>(ri.width) * ri.height;
  px_.reserve(reserve);
  py_.reserve(reserve);
  pz_.reserve(reserve);
  i1_.reserve(reserve);
  for (int y = 0; y < ri.height; ++y) {
    for (int x = 0; x < ri.width; ++x) {
      const double z = rd.at(x, y);
      if (!(z >= options_.min_depth && z <= options_.max_depth)) continue;
      px_.push_back(static_cast<float>((x - K.cx) * ifx * z));
      py_.push_back(static_cast<float>((y - K.cy) * ify * z));
      pz_.push_back(static_cast<float>(z));
      i1_.push_back(ri.at(x, y));
    }
  }
  const std::size_t n = px_.size();
  r_i_.assign(n, 0.0f);
  r_d_.assign(n, 0.0f);
  flags_.assign(n, 0);
  valid_i_.assign(n, 0);
  valid_d_.assign(n, 0);
  qx_.assign(n, 0.0f);
  qy_.assign(n, 0.0f);
  qz_.assign(n, 0.0f);
  gi_u_.assign(n, 0.0f);
  gi_v_.assign(n, 0.0f);
  gd_u_.assign(n, 0.0f);
  gd_v_.assign(n, 0.0f);
  w_i_.assign(n, 0.0f);
  w_d_.assign(n, 0.0f);
  stats_.terms = static_cast<int>(n);
}

std::string RgbdOdometryProblem::name() const {
  const auto& im = reference_->intensity;
  return "rgbd-odometry(level " + std::to_string(reference_->level) + ", " + std::to_string(im.width) + "x" +
         std::to_string(im.height) + (options_.depth_first ? ", F_1 = F_D" : "") + ")";
}

void RgbdOdometryProblem::check_x(const Eigen::VectorXd& x) const {
  if (x.size() != 7) throw Error("RGB-D problem: x must be the 7-vector [t; q], got size " + std::to_string(x.size()));
  if (!x.allFinite()) throw Error("RGB-D problem: x contains NaN or Inf");
  if (x.tail<4>().norm() < 1e-12) throw Error("RGB-D problem: quaternion of x has zero norm");
}

void RgbdOdometryProblem::warp_all(const Eigen::VectorXd& x) {
  check_x(x);
  if (cached_x_.size() == x.size() && cached_x_ == x) return;
  cached_x_.resize(0);
  const WarpContext ctx(se3::from_ambient(x), *current_, options_.occlusion_margin);
  const std::size_t n = px_.size();
  TermWarp w;
  for (std::size_t i = 0; i < n; ++i) {
    ctx.warp(px_[i], py_[i], pz_[i], i1_[i], w);
    flags_[i] = w.flags;
    valid_i_[i] = w.flags & kValidI;
    valid_d_[i] = (w.flags & kValidD) ? 1 : 0;
    r_i_[i] = (w.flags & kValidI) ? static_cast<float>(w.r_i) : 0.0f;
    r_d_[i] = (w.flags & kValidD) ? static_cast<float>(w.r_d) : 0.0f;
    qx_[i] = static_cast<float>(w.qx);
    qy_[i] = static_cast<float>(w.qy);
    qz_[i] = static_cast<float>(w.qz);
    gi_u_[i] = static_cast<float>(w.gi_u);
    gi_v_[i] = static_cast<float>(w.gi_v);
    gd_u_[i] = static_cast<float>(w.gd_u);
    gd_v_[i] = static_cast<float>(w.gd_v);
  }
  cached_x_ = x;
}

void RgbdOdometryProblem::ensure_weights(const Eigen::VectorXd& x) {
  if (have_weights_) return;
  warp_all(x);
  estimate_weights(false);
}

void RgbdOdometryProblem::estimate_weights(bool warm_start) {
  const std::size_t n = px_.size();
  if (options_.joint_weights) {
    stats_.joint_scale = compute_joint_weights(r_i_.data(), r_d_.data(), valid_i_.data(), valid_d_.data(), n,
                                               options_.weights, w_i_.data(), w_d_.data(),
                                               warm_start ? stats_.joint_scale : JointScale{});
    stats_.sigma_intensity = std::sqrt(stats_.joint_scale.s_ii);
    stats_.sigma_depth = std::sqrt(stats_.joint_scale.s_dd);
  } else {
    stats_.sigma_intensity = compute_weights(r_i_.data(), valid_i_.data(), n, options_.weights, w_i_.data(),
                                             warm_start ? stats_.sigma_intensity : 0.0);
    stats_.sigma_depth = compute_weights(r_d_.data(), valid_d_.data(), n, options_.weights, w_d_.data(),
                                         warm_start ? stats_.sigma_depth : 0.0);
  }
  have_weights_ = true;
}

solvers::Linearization RgbdOdometryProblem::linearize(const Eigen::VectorXd& x,
                                                      const solvers::LinearizeOptions& options) {
  const std::size_t n = px_.size();
  {
    solvers::ScopedPhase phase(options.profile, "residuals");
    warp_all(x);
  }
  {
    solvers::ScopedPhase phase(options.profile, "weights");
    if (options.update_weights || !have_weights_) {
      // Warm start: the scale changes little between the iterations of one problem.
      estimate_weights(true);
    }
  }

  solvers::Linearization lin;
  ModelAccumulator acc_i, acc_d;
  solvers::ResidualData full_i, full_d;
  {
    solvers::ScopedPhase phase(options.profile, "normal_equations");
    if (options.want_full) {
      for (auto* f : {&full_i, &full_d}) {
        f->r = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(n));
        f->J = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(n), 6);
        f->w = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(n));
      }
    }
    int valid_i = 0, valid_d = 0;
    double wsum_i = 0.0, wsum_d = 0.0;
    double J[6];
    for (std::size_t k = 0; k < n; ++k) {
      const unsigned char f = flags_[k];
      if (!f) continue;
      const double qx = qx_[k], qy = qy_[k], qz = qz_[k];
      // A term invalid at x has weight 0 in evaluate(), so its weight must be 0 here too;
      // weights kept from an earlier x (update_weights = false) follow the same rule.
      if (f & kValidI) {
        ++valid_i;
        const double w = w_i_[k];
        wsum_i += w;
        jacobian_row(qx, qy, qz, gi_u_[k], gi_v_[k], false, J);
        acc_i.add(J, r_i_[k], w);
        if (options.want_full) {
          full_i.r(k) = r_i_[k];
          full_i.w(k) = w;
          for (int c = 0; c < 6; ++c) full_i.J(k, c) = J[c];
        }
      }
      if (f & kValidD) {
        ++valid_d;
        const double w = w_d_[k];
        wsum_d += w;
        jacobian_row(qx, qy, qz, gd_u_[k], gd_v_[k], true, J);
        acc_d.add(J, r_d_[k], w);
        if (options.want_full) {
          full_d.r(k) = r_d_[k];
          full_d.w(k) = w;
          for (int c = 0; c < 6; ++c) full_d.J(k, c) = J[c];
        }
      }
    }
    stats_.valid_intensity = valid_i;
    stats_.valid_depth = valid_d;
    stats_.weight_sum_intensity = wsum_i;
    stats_.weight_sum_depth = wsum_d;
  }
  solvers::QuadraticModel mi = acc_i.model(), md = acc_d.model();
  stats_.f_intensity = mi.a;
  stats_.f_depth = md.a;
  if (options_.depth_first) {
    lin.f1 = std::move(md);
    lin.f2 = std::move(mi);
  } else {
    lin.f1 = std::move(mi);
    lin.f2 = std::move(md);
  }
  if (options.want_full) {
    if (options_.depth_first) std::swap(full_i, full_d);
    lin.full1 = std::move(full_i);
    lin.full2 = std::move(full_d);
  }
  return lin;
}

std::array<double, 2> RgbdOdometryProblem::evaluate_intensity_depth(const Eigen::VectorXd& x) {
  ensure_weights(x);
  warp_all(x);
  double fi = 0.0, fd = 0.0;
  const std::size_t n = px_.size();
  for (std::size_t k = 0; k < n; ++k) {
    fi += double(w_i_[k]) * r_i_[k] * r_i_[k];
    fd += double(w_d_[k]) * r_d_[k] * r_d_[k];
  }
  return {fi, fd};
}

std::array<double, 2> RgbdOdometryProblem::evaluate(const Eigen::VectorXd& x) {
  const auto f = evaluate_intensity_depth(x);
  if (options_.depth_first) return {f[1], f[0]};
  return f;
}

solvers::ResidualData RgbdOdometryProblem::residuals(int j, const Eigen::VectorXd& x, bool with_jacobian) {
  if (j != 1 && j != 2) throw Error("RGB-D problem: objective index must be 1 or 2, got " + std::to_string(j));
  check_x(x);
  ensure_weights(x);
  const bool depth = (j == 2) != options_.depth_first;
  const WarpContext ctx(se3::from_ambient(x), *current_, options_.occlusion_margin);
  const std::size_t n = px_.size();
  solvers::ResidualData out;
  out.r = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(n));
  out.w = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(n));
  if (with_jacobian) out.J = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(n), 6);
  const std::vector<float>& weights = depth ? w_d_ : w_i_;
  const unsigned char need = depth ? kValidD : kValidI;
  TermWarp w;
  double J[6];
  for (std::size_t k = 0; k < n; ++k) {
    out.w(k) = weights[k];
    ctx.warp(px_[k], py_[k], pz_[k], i1_[k], w);
    if (!(w.flags & need)) continue;
    out.r(k) = depth ? w.r_d : w.r_i;
    if (with_jacobian) {
      if (depth) {
        jacobian_row(w.qx, w.qy, w.qz, w.gd_u, w.gd_v, true, J);
      } else {
        jacobian_row(w.qx, w.qy, w.qz, w.gi_u, w.gi_v, false, J);
      }
      for (int c = 0; c < 6; ++c) out.J(k, c) = J[c];
    }
  }
  return out;
}

}  // namespace bivo::odometry
