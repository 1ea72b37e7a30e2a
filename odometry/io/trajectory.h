#pragma once
// TUM trajectories: lines "timestamp tx ty tz qx qy qz qw", camera-to-world poses T_wc.
#include <ostream>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace bivo::odometry::io {

struct StampedPose {
  double timestamp = 0.0;
  Eigen::Isometry3d T_wc = Eigen::Isometry3d::Identity();
};

using Trajectory = std::vector<StampedPose>;

// Reads a TUM trajectory; '#' comments, blank lines and CRLF are tolerated, and a line
// repeating the previous one exactly is dropped (stamps are strictly increasing). Throws
// bivo::Error naming the file and line on malformed lines, non-finite values, a
// zero-norm quaternion, decreasing timestamps, one timestamp with two different poses, an
// empty list or more lines than input_limits() allow.
Trajectory read_tum_trajectory(const std::string& path);

// Writes atomically with full precision (timestamps to 1e-6 s, poses to 1e-9).
void write_tum_trajectory(const std::string& path, const Trajectory& trajectory);
// The same text to a stream (e.g. one of several StagedOutputs); `path` names it in errors.
void write_tum_trajectory(std::ostream& out, const Trajectory& trajectory, const std::string& path);

// Pose at time t by nearest timestamp, or nullptr when none lies within max_dt seconds.
const StampedPose* nearest_pose(const Trajectory& trajectory, double t, double max_dt);

}  // namespace bivo::odometry::io
