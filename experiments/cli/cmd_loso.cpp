// `bivo loso --sequences DIR... --grid V... --output DIR`: leave-one-sequence-out
// (experiments/loso.h): the method's parameter is chosen on all sequences but the held-out
// one, whose RPE alone is reported. One work unit per sequence x {reference, grid value,
// fixed method} (experiments/study/study.h), so `bivo plan loso` shards it.
#include <memory>

#include "experiments/cli/commands.h"
#include "experiments/cli/tracker_flags.h"
#include "experiments/loso.h"
#include "experiments/output_set.h"
#include "experiments/study/study_plan.h"

namespace bivo::experiments::cli {

StudyFactory add_loso_flags(CLI::App* cmd) {
  struct Args {
    std::shared_ptr<TrackerFlags> tracker;
    LosoOptions o;
    std::string output;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("--sequences", a->o.sequences, "TUM sequence folders with groundtruth.txt (at least 2)")->required();
  cmd->add_option("--method", a->o.method, "the method whose parameter is chosen")->capture_default_str();
  cmd->add_option("--parameter", a->o.parameter,
                  "the numeric tracker option chosen: its JSON key (problem.depth_noise_exponent, policy.trust; policy "
                  "keys also bare: trust, kappa, guard)")
      ->capture_default_str();
  cmd->add_option("--grid", a->o.grid, "candidate values of the parameter")->required();
  cmd->add_option("--reference", a->o.reference, "the method the ratios are taken to")->capture_default_str();
  cmd->add_option("--methods", a->o.methods, "methods reported beside, at their defaults (no choice)");
  cmd->add_option("--cost-budget", a->o.cost_budget,
                  "for a speed setting: only values whose CPU per pair on the other sequences is at most this many "
                  "times --cost-method's are candidates (the cheapest when none is; 0: no budget)")
      ->capture_default_str();
  cmd->add_option("--cost-method", a->o.cost_method,
                  "the method the cost budget is in units of (--reference or one of --methods)")
      ->capture_default_str();
  cmd->add_option("--first-frame", a->o.first_frame, "first associated frame")->capture_default_str();
  cmd->add_option("--max-frames", a->o.max_frames, "frames per run (-1: all)")->capture_default_str();
  a->tracker = std::make_shared<TrackerFlags>(cmd, false);
  cmd->add_option("--output", a->output, "folder for loso.md / loso.csv / runs.csv / pairs.csv")->required();
  return [a] {
    std::vector<NamedPath> inputs = named_paths("--sequences", a->o.sequences);
    inputs.push_back(a->tracker->config_input());
    check_output_folder({"--output", a->output}, inputs);
    LosoOptions o = a->o;
    o.tracker = a->tracker->options();
    return loso_study(o, a->output);
  };
}

void add_loso_command(CLI::App& app) {
  add_study_command(app, "loso",
                    "Leave-one-sequence-out: a method's parameter chosen without the sequence it is reported on",
                    add_loso_flags);
}

}  // namespace bivo::experiments::cli
