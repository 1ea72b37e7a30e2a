// `bivo work STUDY [--shard I/N] [--results DIR]`: runs the I-th of N disjoint slices of a
// study's work units, one result file per unit (experiments/study/study_work.h); finished units
// are skipped, so re-running a killed shard resumes it.
#include <iostream>
#include <memory>

#include "experiments/cli/commands.h"
#include "experiments/output_set.h"
#include "experiments/study/study_work.h"

namespace bivo::experiments::cli {

void add_work_command(CLI::App& app) {
  struct Args {
    std::string study, shard = "0/1", results;
    bool keep_going = false;
  };
  auto a = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("work", "Run one shard of a study planned by `bivo plan` (one result file per unit)");
  cmd->add_option("study", a->study, "study file written by `bivo plan`")->required()->check(CLI::ExistingFile);
  cmd->add_option("--shard", a->shard, "I/N: the I-th (from 0) of N disjoint slices of the units")
      ->capture_default_str();
  cmd->add_option("--results", a->results, "folder of the result files (default: the study's name + .results)");
  add_keep_going_flag(cmd, a->keep_going);
  cmd->callback([a] {
    const Study study = read_study(a->study);
    const ShardSpec shard = parse_shard(a->shard);
    const std::string results = a->results.empty() ? default_results_dir(a->study) : a->results;
    std::vector<NamedPath> inputs = named_paths("a sequence of the study", study_sequences(study));
    inputs.push_back({"the study", a->study});
    check_output_folder({"--results", results}, inputs);
    const WorkSummary summary = work_shard(study, shard, results, std::cerr);
    finish_with_failures(summary.failed, summary.ran, a->keep_going);
  });
}

}  // namespace bivo::experiments::cli
