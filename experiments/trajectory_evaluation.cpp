// `bivo eval`'s engine (trajectory_evaluation.h).
#include "experiments/trajectory_evaluation.h"

#include <cstdio>

#include <iomanip>
#include <sstream>

#include <nlohmann/json.hpp>

#include "odometry/io/trajectory.h"

namespace bivo::experiments {

TrajectoryEvaluation evaluate_trajectory_files(const std::string& groundtruth, const std::string& estimate,
                                               double delta_s, double max_dt) {
  TrajectoryEvaluation e;
  e.groundtruth_path = groundtruth;
  e.estimate_path = estimate;
  e.delta_s = delta_s;
  e.max_dt = max_dt;
  const auto gt = odometry::io::read_tum_trajectory(groundtruth);
  const auto est = odometry::io::read_tum_trajectory(estimate);
  odometry::io::RpeOptions ro;
  ro.delta_s = delta_s;
  ro.max_dt = max_dt;
  odometry::io::AteOptions ao;
  ao.max_dt = max_dt;
  e.rpe = odometry::io::relative_pose_error(gt, est, ro);
  e.ate = odometry::io::absolute_trajectory_error(gt, est, ao);
  return e;
}

std::optional<odometry::io::RpeResult> rpe_if_long_enough(const odometry::io::Trajectory& groundtruth,
                                                          const odometry::io::Trajectory& estimate, double delta_s,
                                                          std::string& why) {
  // Counted as relative_pose_error takes them, so a run it cannot score is "too short", not a failure.
  if (estimate.empty() || odometry::io::rpe_window_count(estimate, delta_s) < 2) {
    const double span = estimate.empty() ? 0.0 : estimate.back().timestamp - estimate.front().timestamp;
    char text[200];
    std::snprintf(text, sizeof text, "too short: the run spans %.3g s, fewer than 2 RPE windows of %g s (--delta)",
                  span, delta_s);
    why = text;
    return std::nullopt;
  }
  odometry::io::RpeOptions ro;
  ro.delta_s = delta_s;
  return odometry::io::relative_pose_error(groundtruth, estimate, ro);
}

bool is_too_short(const std::string& why) { return why.rfind("too short", 0) == 0; }

nlohmann::json evaluation_json(const TrajectoryEvaluation& e) {
  nlohmann::json j;
  j["groundtruth"] = e.groundtruth_path;
  j["estimate"] = e.estimate_path;
  j["delta_s"] = e.delta_s;
  j["max_dt_s"] = e.max_dt;
  j["rpe"] = {{"trans_rmse_m_per_s", e.rpe.trans_rmse},   {"trans_mean", e.rpe.trans_mean},
              {"trans_median", e.rpe.trans_median},       {"trans_max", e.rpe.trans_max},
              {"rot_rmse_deg_per_s", e.rpe.rot_rmse_deg}, {"rot_mean_deg", e.rpe.rot_mean_deg},
              {"rot_max_deg", e.rpe.rot_max_deg},         {"pairs", e.rpe.pairs.size()}};
  nlohmann::json windows = nlohmann::json::array();
  for (const auto& p : e.rpe.pairs) {
    windows.push_back({{"t_est_0", p.t_est_0},
                       {"t_est_1", p.t_est_1},
                       {"t_gt_0", p.t_gt_0},
                       {"t_gt_1", p.t_gt_1},
                       {"trans", p.trans},
                       {"rot_rad", p.rot_rad}});
  }
  j["rpe"]["windows"] = windows;
  j["ate"] = {{"rmse_m", e.ate.rmse},
              {"mean", e.ate.mean},
              {"median", e.ate.median},
              {"max", e.ate.max},
              {"matches", e.ate.errors.size()}};
  return j;
}

namespace {
std::string seconds(double delta_s) {
  std::ostringstream s;
  s << std::setprecision(6) << delta_s;
  return s.str();
}
}  // namespace

std::string rpe_unit(const std::string& unit, double delta_s) {
  return delta_s == 1.0 ? unit + "/s" : unit + " per " + seconds(delta_s) + " s";
}

std::string rpe_windows(double delta_s) { return seconds(delta_s) + "-s windows"; }

std::string evaluation_line(const TrajectoryEvaluation& e, bool as_json) {
  if (as_json) {
    const nlohmann::json line = {{"rpe_trans", e.rpe.trans_rmse},
                                 {"rpe_rot", e.rpe.rot_rmse_deg},
                                 {"ate", e.ate.rmse},
                                 {"pairs", e.rpe.pairs.size()}};
    return line.dump();
  }
  std::ostringstream line;
  line << std::setprecision(6) << "rpe_trans=" << e.rpe.trans_rmse << " rpe_rot=" << e.rpe.rot_rmse_deg
       << " ate=" << e.ate.rmse << " pairs=" << e.rpe.pairs.size();
  return line.str();
}

}  // namespace bivo::experiments
