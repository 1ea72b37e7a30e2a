#pragma once
// SE(3) helpers shared by every layer. Defined in se3.cpp: the bodies instantiate Eigen's
// decompositions, which cost seconds of compile time in every file that includes this one.
//
// Conventions (docs/architecture.md):
//  * a tangent vector is xi = [v; w] (translation first, as the paper's
//    [nu1 nu2 nu3 psi1 psi2 psi3]);
//  * the perturbation is on the LEFT: T (+) d = exp(d^) * T;
//  * the ambient (stored) form of a pose is 7 numbers [tx ty tz qx qy qz qw].
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace bivo::solvers::se3 {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Vector7d = Eigen::Matrix<double, 7, 1>;

inline Eigen::Matrix3d hat(const Eigen::Vector3d& w) {
  Eigen::Matrix3d m;
  m << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return m;
}

// Rodrigues' rotation, with a Taylor expansion near zero so small angles stay exact.
Eigen::Matrix3d so3_exp(const Eigen::Vector3d& w);

// Left Jacobian of SO(3): the V in exp([v;w]) = [R, V v; 0, 1].
Eigen::Matrix3d so3_left_jacobian(const Eigen::Vector3d& w);

Eigen::Isometry3d exp(const Vector6d& xi);
Eigen::Vector3d so3_log(const Eigen::Matrix3d& R);
Vector6d log(const Eigen::Isometry3d& T);

// Left-perturbation retraction: T (+) d = exp(d) * T.
Eigen::Isometry3d retract(const Eigen::Isometry3d& T, const Vector6d& d);

Vector7d to_ambient(const Eigen::Isometry3d& T);
Eigen::Isometry3d from_ambient(const Eigen::Ref<const Eigen::VectorXd>& x);

// Rotation angle of a pose in radians (for error reports).
double rotation_angle(const Eigen::Isometry3d& T);

}  // namespace bivo::solvers::se3
