#pragma once
// Ground-truth relative motion of a frame pair and the error of an estimated motion.
#include <optional>

#include <Eigen/Geometry>

#include "odometry/io/trajectory.h"

namespace bivo::odometry::io {

// Pose at time t interpolated between the two bracketing ground-truth poses (linear in
// translation, slerp in rotation), or nullopt when t lies outside the trajectory or the
// bracketing poses are more than max_gap seconds apart (mocap dropouts).
std::optional<Eigen::Isometry3d> interpolate_pose(const Trajectory& trajectory, double t, double max_gap = 0.05);

// Ground-truth T_21 = T_w2^{-1} T_w1 for frames at times t1 (reference) and t2 (current).
std::optional<Eigen::Isometry3d> groundtruth_motion(const Trajectory& groundtruth, double t1, double t2,
                                                    double max_gap = 0.05);

struct PoseError {
  double translation_m = 0.0;  // |translation of truth^-1 * estimate|
  double rotation_deg = 0.0;   // rotation angle of truth^-1 * estimate
};
PoseError pose_error(const Eigen::Isometry3d& estimate, const Eigen::Isometry3d& truth);

}  // namespace bivo::odometry::io
