// `bivo sweep --sequences DIR... --output DIR`: error vs lambda (log grid, method fixed) and
// vs epsilon (log grid, method bounded) relative to the single-objective run (paper fig. 3).
// One work unit per sequence x {reference, grid point} (experiments/study/study.h).
#include <memory>

#include "experiments/cli/commands.h"
#include "experiments/cli/tracker_flags.h"
#include "experiments/output_set.h"
#include "experiments/parameter_sweep.h"
#include "experiments/study/study_plan.h"

namespace bivo::experiments::cli {

StudyFactory add_sweep_flags(CLI::App* cmd) {
  struct Args {
    std::shared_ptr<TrackerFlags> tracker;
    SweepOptions o;
    double lambda_min = 10, lambda_max = 1e6, eps_min = 1e-5, eps_max = 1e-2;
    int lambda_points = 6, eps_points = 4;
    std::string output;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("--sequences", a->o.sequences, "TUM sequence folders with groundtruth.txt")->required();
  cmd->add_option("--lambda-min", a->lambda_min, "smallest lambda [gray^2/m^2]")->capture_default_str();
  cmd->add_option("--lambda-max", a->lambda_max, "largest lambda")->capture_default_str();
  cmd->add_option("--lambda-points", a->lambda_points, "lambda grid points (0: no lambda sweep)")
      ->capture_default_str()
      ->check(CLI::Range(0, 1000));
  cmd->add_option("--eps-min", a->eps_min, "smallest bound on F_D per unit weight [m^2]")->capture_default_str();
  cmd->add_option("--eps-max", a->eps_max, "largest bound")->capture_default_str();
  cmd->add_option("--eps-points", a->eps_points, "epsilon grid points (0: no epsilon sweep)")
      ->capture_default_str()
      ->check(CLI::Range(0, 1000));
  cmd->add_option("--eps-backend", a->o.epsilon_backend, "backend of the bounded runs (default exact)");
  cmd->add_option("--first-frame", a->o.first_frame, "first associated frame")->capture_default_str();
  cmd->add_option("--max-frames", a->o.max_frames, "frames per run (-1: all)")->capture_default_str();
  cmd->add_option("--delta", a->o.rpe_delta, "RPE window [s] (a run spanning fewer than two gives \"too short\" cells)")
      ->capture_default_str()
      ->check(CLI::Range(1e-3, 1e6));
  a->tracker = std::make_shared<TrackerFlags>(cmd, false);
  cmd->add_option("--output", a->output, "folder for sweep.csv / sweep.json / sweep.md")->required();
  return [a] {
    std::vector<NamedPath> inputs = named_paths("--sequences", a->o.sequences);
    inputs.push_back(a->tracker->config_input());
    check_output_folder({"--output", a->output}, inputs);
    SweepOptions o = a->o;
    if (a->lambda_points > 0) o.lambdas = log_grid(a->lambda_min, a->lambda_max, a->lambda_points);
    if (a->eps_points > 0) o.epsilons = log_grid(a->eps_min, a->eps_max, a->eps_points);
    o.tracker = a->tracker->options();
    return sweep_study(o, a->output);
  };
}

void add_sweep_command(CLI::App& app) {
  add_study_command(app, "sweep", "Error vs lambda and epsilon, as ratios to the single-objective run (paper fig. 3)",
                    add_sweep_flags);
}

}  // namespace bivo::experiments::cli
