// TrackerOptions::retry_from_rest: a pair lost at its motion prior is solved again from rest,
// and the two candidates are compared by how well they align the pair.
#include <limits>
#include <string>

#include "odometry/odometry_methods.h"
#include "odometry/rgbd_problem.h"
#include "odometry/tracker.h"
#include "solvers/geometry/se3.h"

namespace bivo::odometry {
namespace {

// The robust (t-distribution) scale of the method's first objective's residuals (r_I; r_D for
// method depth) at motion T on the finest level solved, on the frames as given: how well T
// aligns the pair, on the terms it keeps in view. +inf when fewer than the tracker's minimum
// of terms are valid.
double residual_scale_at(const PreparedFrame& reference, const PreparedFrame& current, const Eigen::Isometry3d& T,
                         const TrackerOptions& options) {
  RgbdProblemOptions po = method_problem_options(parse_method(options.method), options);
  po.joint_weights = false;
  po.affine_brightness = 0;
  po.jacobian = JacobianKind::kForward;
  po.weights.kind = WeightKind::kTDistribution;
  const int level = options.finest_level;
  RgbdOdometryProblem problem(reference.pyramid.levels[level], current.pyramid.levels[level], po);
  problem.objectives_at(solvers::se3::to_ambient(T));
  const RgbdLinearizationStats& s = problem.last_stats();
  const int valid = po.depth_first ? s.valid_depth : s.valid_intensity;
  if (valid < options.min_valid_pixels) return std::numeric_limits<double>::infinity();
  return po.depth_first ? s.sigma_depth : s.sigma_intensity;
}

}  // namespace

PairResult estimate_motion_from_prior(const PreparedFrame& reference, const PreparedFrame& current,
                                      const Eigen::Isometry3d& prior, const TrackerOptions& options) {
  PairResult first = estimate_motion(reference, current, prior, options);
  if (first.valid || options.retry_from_rest != 1 || prior.isApprox(Eigen::Isometry3d::Identity())) return first;
  PairResult retry = estimate_motion(reference, current, Eigen::Isometry3d::Identity(), options);
  // The solve from rest can end in a wrong minimum that keeps more terms in view than the
  // truth does (fast motion): it replaces the prior only when it aligns the pair better.
  const double cpu0 = process_cpu_seconds();
  const double at_prior = retry.valid ? residual_scale_at(reference, current, prior, options) : 0.0;
  const double at_retry = retry.valid ? residual_scale_at(reference, current, retry.T_21, options) : 0.0;
  if (!retry.valid || !(at_retry <= at_prior)) {  // the prior stands
    first.iterations += retry.iterations;
    first.seconds += retry.seconds;
    first.cpu_seconds += retry.cpu_seconds + (process_cpu_seconds() - cpu0);
    first.note += "; from rest: " + (retry.valid ? "residual scale " + std::to_string(at_retry) +
                                                       " above the prior's " + std::to_string(at_prior)
                                                 : retry.note);
    return first;
  }
  retry.iterations += first.iterations;
  retry.seconds += first.seconds;
  retry.cpu_seconds += first.cpu_seconds + (process_cpu_seconds() - cpu0);
  retry.profile.merge(first.profile);
  retry.note = "from the prior: " + first.note + "; solved from rest";
  return retry;
}

}  // namespace bivo::odometry
