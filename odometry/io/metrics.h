#pragma once
// Trajectory error metrics exactly as the TUM RGB-D benchmark tools define them
// (evaluate_rpe.py with a fixed delta, evaluate_ate.py); formulas in docs/metrics.md.
//
// Usage:
//   auto gt = read_tum_trajectory("groundtruth.txt");
//   auto est = read_tum_trajectory("estimate.txt");
//   RpeResult rpe = relative_pose_error(gt, est);          // 1-second windows
//   AteResult ate = absolute_trajectory_error(gt, est);    // rigid Horn/Umeyama alignment
//   rpe.trans_rmse  [m per delta, i.e. m/s for delta = 1 s]   rpe.rot_rmse_deg [deg/s]
// Both throw bivo::Error when the trajectories do not overlap in time (fewer than two
// matched poses / pairs), naming the time ranges.
#include <vector>

#include <Eigen/Geometry>

#include "odometry/io/timestamp_matching.h"  // associate_timestamps
#include "odometry/io/trajectory.h"

namespace bivo::odometry::io {

struct RpeOptions {
  double delta_s = 1.0;  // window length (evaluate_rpe.py --fixed_delta --delta 1 --delta_unit s)
  // An estimate pose is compared with the ground-truth pose of nearest timestamp when it lies
  // within max_dt seconds (evaluate_rpe.py: twice the median ground-truth interval, which is
  // 0.02 s for TUM's 100 Hz motion capture).
  double max_dt = 0.02;
};

struct RpePair {
  double t_est_0 = 0, t_est_1 = 0;  // estimate stamps of the window's ends
  double t_gt_0 = 0, t_gt_1 = 0;    // matched ground-truth stamps
  double trans = 0;                 // |translation of E| in metres
  double rot_rad = 0;               // rotation angle of E in radians
};

struct RpeResult {
  std::vector<RpePair> pairs;
  double trans_rmse = 0, trans_mean = 0, trans_median = 0, trans_max = 0;  // metres per window
  double rot_rmse_deg = 0, rot_mean_deg = 0, rot_max_deg = 0;              // degrees per window
};

// The windows of delta_s seconds relative_pose_error takes from `estimate` before matching the
// ground truth: one per estimate stamp whose nearest stamp delta_s later is not the last.
int rpe_window_count(const Trajectory& estimate, double delta_s);

// Relative pose error over windows of delta_s seconds of the estimate's own timestamps.
RpeResult relative_pose_error(const Trajectory& groundtruth, const Trajectory& estimate,
                              const RpeOptions& options = {});

struct AteOptions {
  double max_dt = 0.02;  // evaluate_ate.py --max_difference (strict <)
};

struct AteResult {
  std::vector<double> t_est, t_gt;                              // matched stamps, sorted by t_gt
  std::vector<double> errors;                                   // per match: |R p_est + t - p_gt| in metres
  Eigen::Isometry3d alignment = Eigen::Isometry3d::Identity();  // maps estimate into gt frame
  double rmse = 0, mean = 0, median = 0, max = 0;
};

// Absolute trajectory error of positions after the rigid (no scale) least-squares alignment
// of the estimate onto the ground truth (Horn 1987 / Umeyama 1991).
AteResult absolute_trajectory_error(const Trajectory& groundtruth, const Trajectory& estimate,
                                    const AteOptions& options = {});

}  // namespace bivo::odometry::io
