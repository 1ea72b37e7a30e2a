#include "solvers/geometry/se3.h"

#include <cmath>

namespace bivo::solvers::se3 {

// Rodrigues' rotation, with a Taylor expansion near zero so small angles stay exact.
Eigen::Matrix3d so3_exp(const Eigen::Vector3d& w) {
  const double th2 = w.squaredNorm();
  const Eigen::Matrix3d W = hat(w);
  double a, b;
  if (th2 < 1e-10) {
    a = 1.0 - th2 / 6.0;
    b = 0.5 - th2 / 24.0;
  } else {
    const double th = std::sqrt(th2);
    a = std::sin(th) / th;
    b = (1.0 - std::cos(th)) / th2;
  }
  return Eigen::Matrix3d::Identity() + a * W + b * W * W;
}

// Left Jacobian of SO(3): the V in exp([v;w]) = [R, V v; 0, 1].
Eigen::Matrix3d so3_left_jacobian(const Eigen::Vector3d& w) {
  const double th2 = w.squaredNorm();
  const Eigen::Matrix3d W = hat(w);
  double b, c;
  if (th2 < 1e-10) {
    b = 0.5 - th2 / 24.0;
    c = 1.0 / 6.0 - th2 / 120.0;
  } else {
    const double th = std::sqrt(th2);
    b = (1.0 - std::cos(th)) / th2;
    c = (th - std::sin(th)) / (th2 * th);
  }
  return Eigen::Matrix3d::Identity() + b * W + c * W * W;
}

Eigen::Isometry3d exp(const Vector6d& xi) {
  const Eigen::Vector3d v = xi.head<3>();
  const Eigen::Vector3d w = xi.tail<3>();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = so3_exp(w);
  T.translation() = so3_left_jacobian(w) * v;
  return T;
}

Eigen::Vector3d so3_log(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

Vector6d log(const Eigen::Isometry3d& T) {
  const Eigen::Vector3d w = so3_log(T.linear());
  Vector6d xi;
  xi.head<3>() = so3_left_jacobian(w).inverse() * T.translation();
  xi.tail<3>() = w;
  return xi;
}

// Left-perturbation retraction: T (+) d = exp(d) * T.
Eigen::Isometry3d retract(const Eigen::Isometry3d& T, const Vector6d& d) { return exp(d) * T; }

Vector7d to_ambient(const Eigen::Isometry3d& T) {
  Eigen::Quaterniond q(T.linear());
  q.normalize();
  Vector7d x;
  x << T.translation(), q.x(), q.y(), q.z(), q.w();
  return x;
}

Eigen::Isometry3d from_ambient(const Eigen::Ref<const Eigen::VectorXd>& x) {
  Eigen::Quaterniond q(x(6), x(3), x(4), x(5));
  q.normalize();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = q.toRotationMatrix();
  T.translation() = x.head<3>();
  return T;
}

// Rotation angle of a pose in radians (for error reports).
double rotation_angle(const Eigen::Isometry3d& T) { return Eigen::AngleAxisd(T.linear()).angle(); }

}  // namespace bivo::solvers::se3
