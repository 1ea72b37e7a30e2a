// `bivo eval GROUNDTRUTH ESTIMATE [--json] [--output FILE]`: TUM RPE (1-s windows) and ATE
// of an estimated trajectory (odometry/io/metrics.h, docs/metrics.md), printed as one line.
#include <iomanip>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "experiments/cli/commands.h"
#include "odometry/io/atomic_file.h"
#include "odometry/io/metrics.h"
#include "odometry/io/trajectory.h"

namespace bivo::experiments::cli {

void add_eval_command(CLI::App& app) {
  struct Options {
    std::string groundtruth, estimate, output;
    bool json = false;
    double delta = 1.0, max_dt = 0.02;
  };
  auto opt = std::make_shared<Options>();
  auto* cmd = app.add_subcommand(
      "eval", "TUM relative pose error (RPE, 1-s windows) and absolute trajectory error (ATE)");
  cmd->add_option("groundtruth", opt->groundtruth, "ground-truth TUM trajectory")->required();
  cmd->add_option("estimate", opt->estimate, "estimated TUM trajectory")->required();
  cmd->add_flag("--json", opt->json, "print the one line as a JSON object instead of key=value");
  cmd->add_option("--output", opt->output,
                  "also write every statistic and every RPE window to this JSON file");
  cmd->add_option("--delta", opt->delta, "RPE window in seconds")->capture_default_str();
  cmd->add_option("--max-dt", opt->max_dt, "timestamp matching tolerance in seconds")
      ->capture_default_str();
  cmd->footer(
      "Prints one line: rpe_trans=<m/s> rpe_rot=<deg/s> ate=<m> pairs=<number of RPE windows>");
  cmd->callback([opt] {
    const auto gt = odometry::io::read_tum_trajectory(opt->groundtruth);
    const auto est = odometry::io::read_tum_trajectory(opt->estimate);
    odometry::io::RpeOptions ro;
    ro.delta_s = opt->delta;
    ro.max_dt = opt->max_dt;
    odometry::io::AteOptions ao;
    ao.max_dt = opt->max_dt;
    const auto rpe = odometry::io::relative_pose_error(gt, est, ro);
    const auto ate = odometry::io::absolute_trajectory_error(gt, est, ao);
    nlohmann::json j;
    {
      j["groundtruth"] = opt->groundtruth;
      j["estimate"] = opt->estimate;
      j["delta_s"] = opt->delta;
      j["max_dt_s"] = opt->max_dt;
      j["rpe"] = {{"trans_rmse_m_per_s", rpe.trans_rmse}, {"trans_mean", rpe.trans_mean},
                  {"trans_median", rpe.trans_median}, {"trans_max", rpe.trans_max},
                  {"rot_rmse_deg_per_s", rpe.rot_rmse_deg}, {"rot_mean_deg", rpe.rot_mean_deg},
                  {"rot_max_deg", rpe.rot_max_deg}, {"pairs", rpe.pairs.size()}};
      nlohmann::json windows = nlohmann::json::array();
      for (const auto& p : rpe.pairs) {
        windows.push_back({{"t_est_0", p.t_est_0}, {"t_est_1", p.t_est_1}, {"t_gt_0", p.t_gt_0},
                           {"t_gt_1", p.t_gt_1}, {"trans", p.trans}, {"rot_rad", p.rot_rad}});
      }
      j["rpe"]["windows"] = windows;
      j["ate"] = {{"rmse_m", ate.rmse}, {"mean", ate.mean}, {"median", ate.median},
                  {"max", ate.max}, {"matches", ate.errors.size()}};
    }
    if (!opt->output.empty()) {
      odometry::io::write_file_atomically(opt->output, [&](std::ostream& o) { o << j.dump(2) << "\n"; });
    }
    if (opt->json) {
      const nlohmann::json line = {{"rpe_trans", rpe.trans_rmse}, {"rpe_rot", rpe.rot_rmse_deg},
                                   {"ate", ate.rmse}, {"pairs", rpe.pairs.size()}};
      std::cout << line.dump() << std::endl;
      return;
    }
    std::ostringstream line;
    line << std::setprecision(6) << "rpe_trans=" << rpe.trans_rmse << " rpe_rot=" << rpe.rot_rmse_deg
         << " ate=" << ate.rmse << " pairs=" << rpe.pairs.size();
    std::cout << line.str() << std::endl;
  });
}

}  // namespace bivo::experiments::cli
