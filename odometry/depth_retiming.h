#pragma once
// Unsynchronized colour and depth (TUM freiburg1: each depth image taken up to half a frame
// before or after its colour image): a depth image is moved to its colour image's time with
// the pair's own motion, taken as constant velocity over the pair (TrackerOptions::retime_depth).
// The delays are the sequence's own timestamps (depth.txt against rgb.txt), never ground truth.
#include <Eigen/Geometry>

#include "odometry/io/camera_intrinsics.h"
#include "odometry/kernels/kernels.h"
#include "odometry/rgbd_pyramid.h"
#include "solvers/geometry/se3.h"

namespace bivo::odometry {

// The pose, in the camera's frame at time t, of the camera at t + delay when it moves at
// `velocity` about t, log(T_21) per second (q = T_21 p, frame 1 -> frame 2, as
// RgbdOdometryProblem): exp(-delay velocity) (over a pair: exp((delay / interval) log(T_21^-1))).
Eigen::Isometry3d pose_after_delay(const solvers::se3::Vector6d& velocity, double delay);

// `depth` (metres, 0 = missing), taken from the pose `colour_from_depth` in the colour camera's
// frame, as the colour camera sees it: every valid pixel back-projected, moved and projected to
// its nearest pixel, its depth carried to that pixel's centre along the depth image's slope, the
// nearest surface kept where several land; pixels nothing lands on are 0. A forward splat: a
// backward search per pixel was 7x slower for no accuracy on the fast renderings.
// By the best kernels of this CPU, or by those of `isa` (bit-identical results).
ImageF retime_depth(const ImageF& depth, const io::Intrinsics& K, const Eigen::Isometry3d& colour_from_depth);
ImageF retime_depth(const ImageF& depth, const io::Intrinsics& K, const Eigen::Isometry3d& colour_from_depth,
                    KernelIsa isa);

}  // namespace bivo::odometry
