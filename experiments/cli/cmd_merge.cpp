// `bivo merge STUDY [RESULTS_DIR] [--output DIR] [--partial]`: checks that every unit of the
// study has exactly one result file, then writes the tables, JSON/CSV and plots of the
// single-process command (experiments/study/study_merge.h).
#include <iostream>
#include <memory>

#include "experiments/cli/commands.h"
#include "experiments/study/study_merge.h"
#include "experiments/study/study_work.h"
#include "solvers/error.h"

namespace bivo::experiments::cli {

void print_study_output(const MergeOutput& output) {
  std::cout << output.markdown;
  if (output.report) std::cout << "\nreport: " << output.report->report_path << std::endl;
  std::cout << std::flush;
}

void add_study_command(CLI::App& app, const std::string& name, const std::string& description,
                       StudyFactory (*add_flags)(CLI::App*)) {
  auto* cmd = app.add_subcommand(name, description);
  const StudyFactory make = add_flags(cmd);
  cmd->callback([make] { print_study_output(run_study(make(), &std::cerr)); });
}

void add_merge_command(CLI::App& app) {
  struct Args {
    std::string study, results, output;
    bool partial = false;
  };
  auto a = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("merge", "Check a study's result files and write the command's tables and plots");
  cmd->add_option("study", a->study, "study file written by `bivo plan`")->required()->check(CLI::ExistingFile);
  cmd->add_option("results", a->results, "folder of the result files (default: the study's name + .results)");
  cmd->add_option("--output", a->output, "output folder (default: the --output given to `bivo plan`)");
  cmd->add_flag("--partial", a->partial,
                "merge what is there: missing units become empty cells and notes, duplicates use the first file");
  cmd->callback([a] {
    const Study study = read_study(a->study);
    const std::string results = a->results.empty() ? default_results_dir(a->study) : a->results;
    const CollectedResults collected = collect_results(study, results);
    std::cerr << "merge: " << collected.files << " result file(s) in " << results << ": "
              << completeness_text(collected);
    if (!complete(collected) && !a->partial) {
      throw Error("merge: the results in '" + results + "' are incomplete (see above); re-run the missing shards, "
                  "or merge what is there with --partial");
    }
    std::map<std::string, nlohmann::json> by_unit;
    for (const auto& [id, file] : collected.by_unit) by_unit[id] = file.result;
    print_study_output(merge_results(study, by_unit, a->output.empty() ? study.output : a->output));
  });
}

}  // namespace bivo::experiments::cli
