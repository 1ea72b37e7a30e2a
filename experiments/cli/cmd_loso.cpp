// `bivo loso --sequences DIR... --grid V... --output DIR`: leave-one-sequence-out
// (experiments/loso.h): the method's parameters are chosen on all sequences but the held-out
// one, whose RPE alone is reported. Several `--parameter P --grid V...` are chosen together
// (the i-th --grid holds the i-th --parameter's values); `--finest-levels L...` pools runs at
// several finest levels into one choice. One work unit per sequence x finest level x
// {reference, setting, fixed method} (experiments/study/study.h), so `bivo plan loso` shards it.
#include <memory>
#include <string>
#include <vector>

#include "experiments/cli/commands.h"
#include "experiments/cli/tracker_flags.h"
#include "experiments/loso.h"
#include "experiments/output_set.h"
#include "experiments/study/study_plan.h"
#include "solvers/error.h"

namespace bivo::experiments::cli {

namespace {

// The i-th --parameter with the i-th --grid's values.
std::vector<LosoParameter> loso_parameters(const std::vector<std::string>& names,
                                           const std::vector<std::vector<std::string>>& grids) {
  if (names.size() != grids.size()) {
    std::string listed;
    for (const std::string& n : names) listed += (listed.empty() ? "" : ", ") + n;
    throw Error("loso: " + std::to_string(names.size()) + " --parameter (" + listed + ") but " +
                std::to_string(grids.size()) + " --grid: give each --parameter its --grid after it");
  }
  std::vector<LosoParameter> out;
  for (std::size_t k = 0; k < names.size(); ++k) {
    LosoParameter p{names[k], {}};
    for (const std::string& text : grids[k]) {
      double v = 0.0;
      if (!CLI::detail::lexical_cast(text, v))
        throw Error("loso: --grid value '" + text + "' of '" + names[k] + "' is not a number");
      p.grid.push_back(v);
    }
    out.push_back(p);
  }
  return out;
}

}  // namespace

StudyFactory add_loso_flags(CLI::App* cmd) {
  struct Args {
    std::shared_ptr<TrackerFlags> tracker;
    LosoOptions o;
    std::vector<std::string> parameters = {LosoParameter{}.name};
    std::vector<std::vector<std::string>> grids;  // one per --grid, as given
    std::string output;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("--sequences", a->o.sequences, "TUM sequence folders with groundtruth.txt (at least 2)")->required();
  cmd->add_option("--method", a->o.method, "the method whose parameters are chosen")->capture_default_str();
  cmd->add_option("--parameter", a->parameters,
                  "a numeric tracker option chosen: its JSON key (problem.depth_noise_exponent, policy.trust; policy "
                  "keys also bare: trust, kappa, guard); repeated, with a --grid each, the options are chosen together "
                  "over the product of their grids")
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
      ->capture_default_str();
  // Kept per occurrence (CLI11 would merge them, or refuse an empty one before bivo could
  // name it); the numbers are read in the factory, where errors are bivo's.
  cmd->add_option(
         "--grid",
         [a](const CLI::results_t& values) {
           a->grids.push_back(values.size() == 1 && values[0].empty() ? CLI::results_t{} : values);
           return true;
         },
         "candidate values of the parameter (of the i-th --parameter for the i-th --grid)")
      ->type_name("FLOAT")
      ->type_size(1)
      ->expected(0, CLI::detail::expected_max_vector_size)
      ->allow_extra_args()
      ->trigger_on_parse()
      ->required();
  cmd->add_option("--finest-levels", a->o.finest_levels,
                  "finest pyramid levels pooled: every run at each, the choice over all of them at once (instead of "
                  "--finest-level alone)");
  cmd->add_option("--reference", a->o.reference, "the method the ratios are taken to")->capture_default_str();
  cmd->add_option("--methods", a->o.methods, "methods reported beside, at their defaults (no choice)");
  cmd->add_option("--cost-budget", a->o.cost_budget,
                  "for a speed setting: only settings whose CPU per pair on the other sequences (the geometric "
                  "mean of the per-sequence ratios, at each of --finest-levels) is at most this many times "
                  "--cost-method's are candidates (the cheapest when none is; 0: no budget)")
      ->capture_default_str();
  cmd->add_option("--cost-method", a->o.cost_method,
                  "the method the cost budget is in units of (--reference or one of --methods)")
      ->capture_default_str();
  cmd->add_option("--acceptable-ratio", a->o.acceptable_ratio,
                  "settings whose worst ratio to --reference on the other sequences is at most this are chosen by "
                  "the geometric mean of their per-sequence worst ratios (0: the smallest worst ratio always decides)")
      ->capture_default_str();
  cmd->add_option("--first-frame", a->o.first_frame, "first associated frame")->capture_default_str();
  cmd->add_option("--max-frames", a->o.max_frames, "frames per run (-1: all)")->capture_default_str();
  cmd->add_option("--delta", a->o.rpe_delta, "RPE window [s] (every sequence must span two)")
      ->capture_default_str()
      ->check(CLI::Range(1e-3, 1e6));
  a->tracker = std::make_shared<TrackerFlags>(cmd, false);
  cmd->add_option("--output", a->output, "folder for loso.md / loso.csv / runs.csv / pairs.csv")->required();
  return [a] {
    std::vector<NamedPath> inputs = named_paths("--sequences", a->o.sequences);
    inputs.push_back(a->tracker->config_input());
    check_output_folder({"--output", a->output}, inputs);
    LosoOptions o = a->o;
    o.tracker = a->tracker->options();
    o.parameters = loso_parameters(a->parameters, a->grids);
    return loso_study(o, a->output);
  };
}

void add_loso_command(CLI::App& app) {
  add_study_command(app, "loso",
                    "Leave-one-sequence-out: a method's parameters chosen without the sequence they are reported on",
                    add_loso_flags);
}

}  // namespace bivo::experiments::cli
