#include "odometry/io/pose_error.h"

#include <algorithm>
#include <cmath>

#include "solvers/geometry/se3.h"

namespace bivo::odometry::io {

std::optional<Eigen::Isometry3d> interpolate_pose(const Trajectory& trajectory, double t, double max_gap) {
  if (trajectory.empty() || t < trajectory.front().timestamp || t > trajectory.back().timestamp) {
    return std::nullopt;
  }
  const auto it = std::lower_bound(trajectory.begin(), trajectory.end(), t,
                                   [](const StampedPose& p, double time) { return p.timestamp < time; });
  if (it->timestamp == t) return it->T_wc;
  const StampedPose& hi = *it;
  const StampedPose& lo = *(it - 1);
  const double gap = hi.timestamp - lo.timestamp;
  if (!(gap > 0.0) || gap > max_gap) return std::nullopt;
  const double s = (t - lo.timestamp) / gap;
  const Eigen::Quaterniond q0(lo.T_wc.linear()), q1(hi.T_wc.linear());
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = q0.slerp(s, q1).normalized().toRotationMatrix();
  T.translation() = (1.0 - s) * lo.T_wc.translation() + s * hi.T_wc.translation();
  return T;
}

std::optional<Eigen::Isometry3d> groundtruth_motion(const Trajectory& groundtruth, double t1, double t2,
                                                    double max_gap) {
  const auto T1 = interpolate_pose(groundtruth, t1, max_gap);
  const auto T2 = interpolate_pose(groundtruth, t2, max_gap);
  if (!T1 || !T2) return std::nullopt;
  return Eigen::Isometry3d(T2->inverse() * (*T1));
}

PoseError pose_error(const Eigen::Isometry3d& estimate, const Eigen::Isometry3d& truth) {
  const Eigen::Isometry3d E = truth.inverse() * estimate;
  return {E.translation().norm(), solvers::se3::rotation_angle(E) * 180.0 / M_PI};
}

}  // namespace bivo::odometry::io
