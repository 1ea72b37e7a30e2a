#include "odometry/io/metrics.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <Eigen/Geometry>

#include "solvers/error.h"

namespace bivo::odometry::io {
namespace {

std::vector<double> stamps_of(const Trajectory& t) {
  std::vector<double> s;
  s.reserve(t.size());
  for (const auto& p : t) s.push_back(p.timestamp);
  return s;
}

// Index of the stamp nearest to t (ties to the earlier one); `sorted` must be non-empty.
int closest_index(const std::vector<double>& sorted, double t) {
  const auto it = std::lower_bound(sorted.begin(), sorted.end(), t);
  if (it == sorted.begin()) return 0;
  if (it == sorted.end()) return int(sorted.size()) - 1;
  const auto prev = std::prev(it);
  return int((t - *prev <= *it - t) ? prev - sorted.begin() : it - sorted.begin());
}

// Rotation angle of R, the arccos((trace R - 1)/2) of evaluate_rpe.py's compute_angle written
// with atan2 so that small angles keep full precision.
double rotation_angle(const Eigen::Matrix3d& R) {
  const double c = 0.5 * (R.trace() - 1.0);
  const Eigen::Vector3d axis(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1));
  return std::atan2(0.5 * axis.norm(), c);
}

double rms(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x * x;
  return std::sqrt(s / double(v.size()));
}

double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return s / double(v.size());
}

// numpy.median: mean of the two middle values for even sizes.
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string range_text(const Trajectory& t) {
  std::ostringstream s;
  s.precision(17);
  s << "[" << t.front().timestamp << ", " << t.back().timestamp << "] (" << t.size() << " poses)";
  return s.str();
}

// evaluate_rpe.py --fixed_delta: the window from estimate frame i ends at the estimate frame
// nearest to t_i + delta; windows whose end falls on the last frame are skipped (the script's
// `if j != len-1`), which also drops every window reaching past the end of the estimate.
// -1: no window from i.
int window_end(const std::vector<double>& est_stamps, int i, double delta_s) {
  const int j = closest_index(est_stamps, est_stamps[i] + delta_s);
  return j == int(est_stamps.size()) - 1 ? -1 : j;
}

}  // namespace

int rpe_window_count(const Trajectory& estimate, double delta_s) {
  const std::vector<double> est_stamps = stamps_of(estimate);
  int count = 0;
  for (int i = 0; i < int(est_stamps.size()); ++i) count += window_end(est_stamps, i, delta_s) >= 0;
  return count;
}

RpeResult relative_pose_error(const Trajectory& groundtruth, const Trajectory& estimate, const RpeOptions& options) {
  if (groundtruth.empty() || estimate.empty()) throw Error("relative_pose_error: empty trajectory");
  if (!(options.delta_s > 0) || !(options.max_dt >= 0)) {
    throw Error("relative_pose_error: delta must be > 0 and max_dt >= 0 (got delta=" + std::to_string(options.delta_s) +
                ", max_dt=" + std::to_string(options.max_dt) + ")");
  }
  const std::vector<double> gt_stamps = stamps_of(groundtruth);
  const std::vector<double> est_stamps = stamps_of(estimate);
  const int n = int(estimate.size());

  RpeResult result;
  for (int i = 0; i < n; ++i) {
    const int j = window_end(est_stamps, i, options.delta_s);
    if (j < 0) continue;
    const int g0 = closest_index(gt_stamps, est_stamps[i]);
    const int g1 = closest_index(gt_stamps, est_stamps[j]);
    if (std::abs(gt_stamps[g0] - est_stamps[i]) > options.max_dt ||
        std::abs(gt_stamps[g1] - est_stamps[j]) > options.max_dt) {
      continue;
    }
    // evaluate_rpe.py: error44 = ominus(ominus(est_j, est_i), ominus(gt_j, gt_i)) with
    // ominus(a, b) = a^-1 b, i.e. error = (E_j^-1 E_i)^-1 (G_j^-1 G_i) = M_e M_g^-1 with the
    // window's motion M = X_i^-1 X_j (docs/metrics.md).
    const Eigen::Isometry3d est_motion = estimate[i].T_wc.inverse() * estimate[j].T_wc;
    const Eigen::Isometry3d gt_motion = groundtruth[g0].T_wc.inverse() * groundtruth[g1].T_wc;
    const Eigen::Isometry3d error = est_motion * gt_motion.inverse();
    RpePair p;
    p.t_est_0 = est_stamps[i];
    p.t_est_1 = est_stamps[j];
    p.t_gt_0 = gt_stamps[g0];
    p.t_gt_1 = gt_stamps[g1];
    p.trans = error.translation().norm();
    p.rot_rad = rotation_angle(error.linear());
    result.pairs.push_back(p);
  }
  if (result.pairs.size() < 2) {
    throw Error("relative_pose_error: fewer than 2 windows of " + std::to_string(options.delta_s) +
                " s match the ground truth within " + std::to_string(options.max_dt) + " s (estimate " +
                range_text(estimate) + ", ground truth " + range_text(groundtruth) +
                "); do the timestamps overlap and is the estimate longer than one window?");
  }
  std::vector<double> trans, rot_deg;
  for (const auto& p : result.pairs) {
    trans.push_back(p.trans);
    rot_deg.push_back(p.rot_rad * 180.0 / M_PI);
  }
  result.trans_rmse = rms(trans);
  result.trans_mean = mean(trans);
  result.trans_median = median(trans);
  result.trans_max = *std::max_element(trans.begin(), trans.end());
  result.rot_rmse_deg = rms(rot_deg);
  result.rot_mean_deg = mean(rot_deg);
  result.rot_max_deg = *std::max_element(rot_deg.begin(), rot_deg.end());
  return result;
}

AteResult absolute_trajectory_error(const Trajectory& groundtruth, const Trajectory& estimate,
                                    const AteOptions& options) {
  if (groundtruth.empty() || estimate.empty()) {
    throw Error("absolute_trajectory_error: empty trajectory");
  }
  const auto matches = associate_timestamps(stamps_of(groundtruth), stamps_of(estimate), options.max_dt);
  if (matches.size() < 3) {
    // Three non-collinear points fix a rigid alignment; with fewer the error is meaningless.
    throw Error("absolute_trajectory_error: only " + std::to_string(matches.size()) +
                " estimate poses match a ground-truth stamp within " + std::to_string(options.max_dt) +
                " s (estimate " + range_text(estimate) + ", ground truth " + range_text(groundtruth) +
                "); need at least 3 — do the timestamps overlap?");
  }
  const int m = int(matches.size());
  Eigen::Matrix3Xd est(3, m), gt(3, m);
  AteResult result;
  for (int k = 0; k < m; ++k) {
    gt.col(k) = groundtruth[matches[k].first].T_wc.translation();
    est.col(k) = estimate[matches[k].second].T_wc.translation();
    result.t_gt.push_back(groundtruth[matches[k].first].timestamp);
    result.t_est.push_back(estimate[matches[k].second].timestamp);
  }
  // evaluate_ate.py align(): rotation and translation only (Horn); Umeyama without scaling is
  // the same least-squares solution, with the reflection guard.
  const Eigen::Matrix4d A = Eigen::umeyama(est, gt, /*with_scaling=*/false);
  result.alignment.matrix() = A;
  for (int k = 0; k < m; ++k) {
    result.errors.push_back((result.alignment * Eigen::Vector3d(est.col(k)) - gt.col(k)).norm());
  }
  result.rmse = rms(result.errors);
  result.mean = mean(result.errors);
  result.median = median(result.errors);
  result.max = *std::max_element(result.errors.begin(), result.errors.end());
  return result;
}

}  // namespace bivo::odometry::io
