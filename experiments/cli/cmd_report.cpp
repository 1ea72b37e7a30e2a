// `bivo report --sequences DIR... --output DIR`: one Markdown report with tables and plots
// (experiments/report_builder.h). Its work units are those of its table, its sweep and
// one Pareto pair per sequence (experiments/study/study.h).
#include <memory>

#include "experiments/cli/commands.h"
#include "experiments/cli/tracker_flags.h"
#include "experiments/output_set.h"
#include "experiments/report_builder.h"
#include "experiments/study/study_plan.h"

namespace bivo::experiments::cli {

StudyFactory add_report_flags(CLI::App* cmd) {
  struct Args {
    std::shared_ptr<TrackerFlags> tracker;
    ReportOptions o;
    std::vector<std::string> methods{"single", "depth", "tykkala", "weighted", "bounded"};
    double lambda_min = 10, lambda_max = 1e6, eps_min = 1e-5, eps_max = 1e-2;
    int lambda_points = 5, eps_points = 4;
    std::string output;
    bool no_pareto = false, no_plots = false;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("--sequences", a->o.sequences, "TUM sequence folders")->required();
  cmd->add_option("--methods", a->methods, "methods ('method' or 'method:backend')")->capture_default_str();
  cmd->add_option("--output", a->output, "report folder (report.md, images/, tables/, sweep/, pareto/)")->required();
  cmd->add_option("--title", a->o.title, "report title")->capture_default_str();
  cmd->add_option("--first-frame", a->o.first_frame, "first associated frame")->capture_default_str();
  cmd->add_option("--max-frames", a->o.max_frames, "frames per sequence for the tables (-1: all)")
      ->capture_default_str();
  cmd->add_option("--delta", a->o.rpe_delta, "RPE window [s] (a run spanning fewer than two gives \"too short\" cells)")
      ->capture_default_str()
      ->check(CLI::Range(1e-3, 1e6));
  cmd->add_option("--sweep-frames", a->o.sweep_max_frames, "frames per sweep run")->capture_default_str();
  cmd->add_option("--lambda-points", a->lambda_points, "lambda grid points (0: none)")
      ->capture_default_str()
      ->check(CLI::Range(0, 1000));
  cmd->add_option("--lambda-min", a->lambda_min, "smallest lambda")->capture_default_str();
  cmd->add_option("--lambda-max", a->lambda_max, "largest lambda")->capture_default_str();
  cmd->add_option("--eps-points", a->eps_points, "epsilon grid points (0: none)")
      ->capture_default_str()
      ->check(CLI::Range(0, 1000));
  cmd->add_option("--eps-min", a->eps_min, "smallest epsilon per unit weight [m^2]")->capture_default_str();
  cmd->add_option("--eps-max", a->eps_max, "largest epsilon")->capture_default_str();
  a->tracker = std::make_shared<TrackerFlags>(cmd, false);
  cmd->add_option("--pareto-level", a->o.pareto_level, "pyramid level of the Pareto fronts")->capture_default_str();
  cmd->add_option("--pareto-points", a->o.pareto_points, "points per Pareto sweep")
      ->capture_default_str()
      ->check(CLI::Range(2, 1000));
  cmd->add_flag("--no-pareto", a->no_pareto, "skip the Pareto fronts");
  cmd->add_flag("--no-plots", a->no_plots, "tables only (no matplotlib)");
  return [a] {
    std::vector<NamedPath> inputs = named_paths("--sequences", a->o.sequences);
    inputs.push_back(a->tracker->config_input());
    check_output_folder({"--output", a->output}, inputs);
    ReportOptions o = a->o;
    for (const auto& m : a->methods) o.methods.push_back(parse_method_spec(m));
    if (a->lambda_points > 0) o.lambdas = log_grid(a->lambda_min, a->lambda_max, a->lambda_points);
    if (a->eps_points > 0) o.epsilons = log_grid(a->eps_min, a->eps_max, a->eps_points);
    o.tracker = a->tracker->options();
    o.pareto = !a->no_pareto;
    o.plots = !a->no_plots;
    return report_study(o, a->output);
  };
}

void add_report_command(CLI::App& app) {
  add_study_command(app, "report", "One Markdown report: tables, per-frame errors, sweeps, Pareto fronts, runtimes",
                    add_report_flags);
}

}  // namespace bivo::experiments::cli
