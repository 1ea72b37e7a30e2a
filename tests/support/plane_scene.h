#pragma once
// A procedural RGB-D pair for the odometry tests: a slanted plane (n.P = 1.6 m) carrying a sum
// of sines, with holes in the depth, seen from two poses; needs no data files.
#include <algorithm>
#include <cmath>
#include <cstddef>

#include <Eigen/Geometry>

#include "odometry/tracker.h"
#include "solvers/geometry/se3.h"

namespace bivo::testing {

inline const odometry::io::Intrinsics kK{260.0, 258.0, 159.5, 119.5};

// The plane n.P = 1.6 m (world = camera 1), a sum of sines on it, each row v seen by a camera at
// pose_of_row(v) (a rolling shutter; one pose for all rows: a global shutter).
template <class PoseOfRow>
odometry::io::RgbdImage render_plane_rows(const PoseOfRow& pose_of_row, int width = 320, int height = 240) {
  const Eigen::Vector3d n = Eigen::Vector3d(0.15, -0.1, 1.0).normalized();
  const double d = 1.6;
  odometry::io::RgbdImage im;
  im.width = width;
  im.height = height;
  im.intensity.resize(static_cast<std::size_t>(width) * height);
  im.depth.resize(im.intensity.size());
  for (int v = 0; v < height; ++v) {
    const Eigen::Isometry3d T_wc = pose_of_row(v);
    const Eigen::Matrix3d R = T_wc.linear();
    const Eigen::Vector3d c = T_wc.translation();
    for (int u = 0; u < width; ++u) {
      const Eigen::Vector3d ray((u - kK.cx) / kK.fx, (v - kK.cy) / kK.fy, 1.0);
      const Eigen::Vector3d ray_w = R * ray;
      const double s = (d - n.dot(c)) / n.dot(ray_w);  // P_w = c + s ray_w, camera depth = s
      const Eigen::Vector3d P = c + s * ray_w;
      const double t = 128.0 + 45.0 * std::sin(9.0 * P.x() + 2.0 * P.y()) + 35.0 * std::cos(7.0 * P.y() - 3.0 * P.x()) +
                       20.0 * std::sin(23.0 * P.x()) * std::sin(19.0 * P.y());
      const std::size_t k = static_cast<std::size_t>(v) * width + u;
      im.intensity[k] = static_cast<float>(t);
      const bool hole = (u * 7 + v * 13) % 41 == 0 || (u > 250 && u < 270 && v > 30 && v < 60);
      im.depth[k] = hole ? 0.0f : static_cast<float>(s);
    }
  }
  return im;
}

// The plane seen by a camera at T_wc (a global shutter).
inline odometry::io::RgbdImage render_plane(const Eigen::Isometry3d& T_wc, int width = 320, int height = 240) {
  return render_plane_rows([&T_wc](int) { return T_wc; }, width, height);
}

// A camera-fixed radial fall-off (vignetting): each intensity times 1 - k rho^2, rho the
// pixel's normalized distance to the principal point ((u - cx) / fx, (v - cy) / fy).
inline void vignette(odometry::io::RgbdImage& im, double k) {
  for (int v = 0; v < im.height; ++v) {
    for (int u = 0; u < im.width; ++u) {
      const double xn = (u - kK.cx) / kK.fx, yn = (v - kK.cy) / kK.fy;
      float& i = im.intensity[static_cast<std::size_t>(v) * im.width + u];
      i = static_cast<float>(i * (1.0 - k * (xn * xn + yn * yn)));
    }
  }
}

inline Eigen::Isometry3d camera2() {
  solvers::se3::Vector6d xi;
  xi << 0.012, -0.008, 0.015, 0.01, -0.012, 0.006;
  return solvers::se3::exp(xi);
}

// The camera at fraction s of the scene's motion (constant velocity from identity to camera2()).
inline Eigen::Isometry3d camera_at(double s) { return solvers::se3::exp(s * solvers::se3::log(camera2())); }

struct Scene {
  odometry::PreparedFrame reference, current;
  Eigen::Isometry3d T_21;  // camera 1 -> camera 2 coordinates
  Scene() {
    const Eigen::Isometry3d T_wc2 = camera2();
    reference = odometry::prepare_frame(render_plane(Eigen::Isometry3d::Identity()), kK, 3);
    current = odometry::prepare_frame(render_plane(T_wc2), kK, 3);
    T_21 = T_wc2.inverse();
  }
};

inline const Scene& scene() {
  static const Scene s;
  return s;
}

// Near the truth, so most terms are valid with residuals of a few gray levels.
inline Eigen::VectorXd near_truth() {
  solvers::se3::Vector6d off;
  off << 0.003, 0.002, -0.002, -0.002, 0.003, 0.001;
  return solvers::se3::to_ambient(solvers::se3::exp(off) * scene().T_21);
}

inline double rel(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) { return (a - b).norm() / b.norm(); }

// The larger of an estimate's translation error in cm and its rotation error in degrees.
inline double cm_or_deg(const Eigen::Isometry3d& estimate, const Eigen::Isometry3d& truth) {
  const Eigen::Isometry3d E = truth.inverse() * estimate;
  return std::max(E.translation().norm() / 0.01, solvers::se3::rotation_angle(E) * 180.0 / M_PI);
}

}  // namespace bivo::testing
