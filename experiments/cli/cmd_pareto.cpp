// `bivo pareto SEQUENCE_DIR (--pair K | --every K) --output DIR`: Pareto fronts (F_I, F_D) of
// frame pairs by lambda and epsilon sweeps, with the methods' picks, the knee and pose errors
// (experiments/pareto_study.h); JSON per pair plus a PNG per pair and a Markdown summary.
// One work unit per pair (experiments/study/study.h).
#include <memory>

#include "experiments/cli/commands.h"
#include "experiments/cli/tracker_flags.h"
#include "experiments/output_set.h"
#include "experiments/pareto_study.h"
#include "experiments/study/study_plan.h"

namespace bivo::experiments::cli {

StudyFactory add_pareto_flags(CLI::App* cmd) {
  struct Args {
    std::shared_ptr<TrackerFlags> tracker;
    ParetoStudyOptions o;
    int pair = -1, every = -1, max_pairs = 5;
    std::string output;
    bool no_plots = false;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("sequence", a->o.sequence_dir, "TUM sequence folder")->required();
  auto* pair_opt = cmd->add_option("--pair", a->pair, "one pair: reference frame K, current K+1");
  auto* every_opt = cmd->add_option("--every", a->every, "every K-th pair (0, K, 2K, ...)");
  pair_opt->excludes(every_opt);
  cmd->add_option("--max-pairs", a->max_pairs, "with --every: at most this many pairs")->capture_default_str();
  cmd->add_option("--level", a->o.level, "pyramid level of the problem (0 = full resolution)")->capture_default_str();
  a->tracker = std::make_shared<TrackerFlags>(cmd, false);
  cmd->add_option("--points", a->o.points, "points per sweep")->capture_default_str()->check(CLI::Range(2, 1000));
  cmd->add_option("--backend", a->o.backend,
                  "solver backend of the sweeps it can solve (weighted sum: the lambda sweep instead of gn; "
                  "epsilon-constraint: the epsilon sweep instead of exact; see `bivo run --help`)");
  cmd->add_option("--lambda-min", a->o.lambda_min, "smallest lambda of the sweep")->capture_default_str();
  cmd->add_option("--lambda-max", a->o.lambda_max, "largest lambda of the sweep")->capture_default_str();
  cmd->add_option("--methods", a->o.methods, "methods whose picks are marked")->capture_default_str();
  cmd->add_option("--output", a->output, "folder for pareto_pair<K>.json/.png and pareto.md")->required();
  cmd->add_flag("--no-plots", a->no_plots, "write the JSON only (no matplotlib)");
  return [a] {
    check_output_folder({"--output", a->output}, {{"sequence", a->o.sequence_dir}, a->tracker->config_input()});
    ParetoStudyOptions o = a->o;
    o.tracker = a->tracker->options();
    const std::vector<int> pairs = pareto_pairs(o.sequence_dir, a->pair, a->every, a->max_pairs);
    return pareto_pairs_study(o, pairs, a->output, !a->no_plots);
  };
}

void add_pareto_command(CLI::App& app) {
  add_study_command(app, "pareto", "Pareto fronts (F_I, F_D) of frame pairs by lambda and epsilon sweeps",
                    add_pareto_flags);
}

}  // namespace bivo::experiments::cli
