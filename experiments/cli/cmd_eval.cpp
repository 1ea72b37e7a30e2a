// `bivo eval GROUNDTRUTH ESTIMATE [--json] [--output FILE]`: TUM RPE (1-s windows) and ATE
// of an estimated trajectory (odometry/io/metrics.h, docs/metrics.md), printed as one line.
#include <iostream>

#include <nlohmann/json.hpp>

#include "experiments/cli/commands.h"
#include "experiments/output_set.h"
#include "experiments/trajectory_evaluation.h"
#include "odometry/io/atomic_file.h"

namespace bivo::experiments::cli {

void add_eval_command(CLI::App& app) {
  struct Options {
    std::string groundtruth, estimate, output;
    bool json = false;
    double delta = 1.0, max_dt = 0.02;
  };
  auto opt = std::make_shared<Options>();
  auto* cmd =
      app.add_subcommand("eval", "TUM relative pose error (RPE, 1-s windows) and absolute trajectory error (ATE)");
  cmd->add_option("groundtruth", opt->groundtruth, "ground-truth TUM trajectory")->required();
  cmd->add_option("estimate", opt->estimate, "estimated TUM trajectory")->required();
  cmd->add_flag("--json", opt->json, "print the one line as a JSON object instead of key=value");
  cmd->add_option("--output", opt->output, "also write every statistic and every RPE window to this JSON file");
  cmd->add_option("--delta", opt->delta, "RPE window in seconds")->capture_default_str();
  cmd->add_option("--max-dt", opt->max_dt, "timestamp matching tolerance in seconds")->capture_default_str();
  cmd->footer(
      "Prints one line: rpe_trans=<m per window> rpe_rot=<deg per window> ate=<m> pairs=<number of RPE windows> "
      "(per window of --delta s: m/s and deg/s at the default 1 s)");
  cmd->callback([opt] {
    check_output_files({{"--output", opt->output}}, {{"groundtruth", opt->groundtruth}, {"estimate", opt->estimate}});
    const TrajectoryEvaluation e = evaluate_trajectory_files(opt->groundtruth, opt->estimate, opt->delta, opt->max_dt);
    if (!opt->output.empty()) {
      odometry::io::write_file_atomically(opt->output,
                                          [&](std::ostream& o) { o << evaluation_json(e).dump(2) << "\n"; });
    }
    std::cout << evaluation_line(e, opt->json) << std::endl;
  });
}

}  // namespace bivo::experiments::cli
