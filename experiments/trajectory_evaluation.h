#pragma once
// Evaluation of one estimated trajectory against ground truth, as `bivo eval` reports it:
// TUM RPE over windows of delta seconds and ATE (odometry/io/metrics.h, docs/metrics.md).
#include <optional>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "odometry/io/metrics.h"

namespace bivo::experiments {

struct TrajectoryEvaluation {
  std::string groundtruth_path, estimate_path;
  double delta_s = 1.0, max_dt = 0.02;
  odometry::io::RpeResult rpe;
  odometry::io::AteResult ate;
};

// Reads both TUM trajectories and evaluates them (bivo::Error names a bad file/line).
TrajectoryEvaluation evaluate_trajectory_files(const std::string& groundtruth, const std::string& estimate,
                                               double delta_s = 1.0, double max_dt = 0.02);

// The RPE of a run over windows of delta_s seconds, or nullopt with `why` = "too short: ..."
// when the estimate spans fewer than the two windows RPE needs (a short run is a result to
// show, not an error); other failures (no overlap with the ground truth) throw bivo::Error.
std::optional<odometry::io::RpeResult> rpe_if_long_enough(const odometry::io::Trajectory& groundtruth,
                                                          const odometry::io::Trajectory& estimate, double delta_s,
                                                          std::string& why);
// The unit of an RPE over windows of delta_s seconds, of a quantity in `unit` ("m", "deg"):
// "m/s" for the TUM benchmark's 1-s windows, else "m per 0.5 s" (RPE is per window, not
// per second). rpe_windows(delta_s): "1-s windows", "0.5-s windows".
std::string rpe_unit(const std::string& unit, double delta_s);
std::string rpe_windows(double delta_s);
// Whether a note or error says "too short" (rpe_if_long_enough).
bool is_too_short(const std::string& why);

// Every statistic and every RPE window (the file of `bivo eval --output`).
nlohmann::json evaluation_json(const TrajectoryEvaluation& e);
// The one line: "rpe_trans=<m/s> rpe_rot=<deg/s> ate=<m> pairs=<windows>", or as JSON.
std::string evaluation_line(const TrajectoryEvaluation& e, bool as_json);

}  // namespace bivo::experiments
