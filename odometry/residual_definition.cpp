#include "odometry/residual_definition.h"

#include <cmath>

namespace bivo::odometry {
namespace {

// Everything one term needs at one pose, in double.
struct TermWarp {
  double r_i = 0.0, r_d = 0.0;
  double qx = 0.0, qy = 0.0, qz = 0.0;
  double gi_u = 0.0, gi_v = 0.0;  // fx dI_2/du, fy dI_2/dv at y
  double gd_u = 0.0, gd_v = 0.0;  // fx dD_2/du, fy dD_2/dv at y
  bool valid_i = false, valid_d = false;
};

struct WarpContext {
  double R[9], t[3];
  double fx, fy, cx, cy;
  int width, height;
  const float* intensity;
  const float* depth;
  double occlusion_margin;
  double min_z = 1e-6;

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
  }

  // Bilinear interpolation of I_2 and D_2 with exact derivatives inside the pixel cell of y
  // (the interpolant is continuous; its derivative jumps across cell borders).
  void warp(double px, double py, double pz, double i1, TermWarp& o) const {
    o = TermWarp{};
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
    if (d00 > 0.0 && d10 > 0.0 && d01 > 0.0 && d11 > 0.0) {
      const double d2 = (1 - b) * ((1 - a) * d00 + a * d10) + b * ((1 - a) * d01 + a * d11);
      if (Z > d2 + occlusion_margin) return;  // occluded in frame 2: neither residual is meaningful
      o.r_d = d2 - Z;
      o.gd_u = fx * ((1 - b) * (d10 - d00) + b * (d11 - d01));
      o.gd_v = fy * ((1 - a) * (d01 - d00) + a * (d11 - d10));
      o.valid_d = true;
    }
    const double i2 = (1 - b) * ((1 - a) * i00 + a * i10) + b * ((1 - a) * i01 + a * i11);
    o.r_i = i2 - i1;
    o.gi_u = fx * ((1 - b) * (i10 - i00) + b * (i11 - i01));
    o.gi_v = fy * ((1 - a) * (i01 - i00) + a * (i11 - i10));
    o.valid_i = true;
  }
};

// J = [c, q x c] of a residual whose image gradient (times focal lengths) is (gu, gv);
// minus_z subtracts d[q]_z/dq = e_z (the r_D term).
void jacobian_row(double qx, double qy, double qz, double gu, double gv, bool minus_z, double J[6]) {
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

}  // namespace

solvers::ResidualData double_residuals(const ReferenceTerms& ref, const RgbdLevel& current, const Eigen::Isometry3d& T,
                                       bool depth, bool with_jacobian, const float* weights,
                                       const DoublePathOptions& options) {
  const WarpContext ctx(T, current, options.occlusion_margin);
  const Eigen::Index n = static_cast<Eigen::Index>(ref.count);
  solvers::ResidualData out;
  out.r = Eigen::VectorXd::Zero(n);
  out.w = Eigen::VectorXd::Zero(n);
  if (with_jacobian) out.J = Eigen::MatrixXd::Zero(n, 6);
  const bool reference_g = options.gradients != GradientSource::kCurrent;
  const double own = options.gradients == GradientSource::kAverage ? 0.5 : 1.0;
  const float* ref_gu = depth ? ref.gd_u.data() : ref.gi_u.data();
  const float* ref_gv = depth ? ref.gd_v.data() : ref.gi_v.data();
  TermWarp w;
  double J[6];
  for (Eigen::Index k = 0; k < n; ++k) {
    out.w(k) = weights[k];
    const double i1 = ref.intensity[k];
    ctx.warp(ref.x[k], ref.y[k], ref.z[k], options.gain * i1 + options.offset, w);
    if (!(depth ? w.valid_d : w.valid_i)) continue;
    out.r(k) = depth ? w.r_d : w.r_i;
    const bool radial = !depth && options.radial != 0.0;
    double xn = 0.0, yn = 0.0;
    if (radial) {
      xn = w.qx / w.qz;
      yn = w.qy / w.qz;
      const double rx = ref.x[k] / ref.z[k], ry = ref.y[k] / ref.z[k];
      out.r(k) -= options.radial * i1 * (xn * xn + yn * yn - rx * rx - ry * ry);
    }
    if (depth && options.depth_noise_exponent != 0) out.r(k) *= std::pow(1.0 / ref.z[k], options.depth_noise_exponent);
    if (!with_jacobian) continue;
    double gu = depth ? w.gd_u : w.gi_u, gv = depth ? w.gd_v : w.gi_v;
    if (options.gradients == GradientSource::kReference) gu = gv = 0.0;
    if (reference_g) {
      gu = own * (gu + ref_gu[k]);
      gv = own * (gv + ref_gv[k]);
    }
    if (radial) {
      // -radial I_1 rho_y^2: fx d/du = -2 radial I_1 x_n, fy d/dv = -2 radial I_1 y_n.
      gu -= 2.0 * options.radial * i1 * xn;
      gv -= 2.0 * options.radial * i1 * yn;
    }
    jacobian_row(w.qx, w.qy, w.qz, gu, gv, depth, J);
    for (int c = 0; c < 6; ++c) out.J(k, c) = J[c];
    if (depth && options.depth_noise_exponent != 0)
      out.J.row(k) *= std::pow(1.0 / ref.z[k], options.depth_noise_exponent);
  }
  return out;
}

}  // namespace bivo::odometry
