// `bivo merge STUDY [RESULTS_DIR] [--output DIR] [--partial]`: checks that every unit of the
// study has exactly one result file, then writes the tables, JSON/CSV and plots of the
// single-process command (experiments/study/study_merge.h).
#include <iostream>
#include <memory>

#include "experiments/cli/commands.h"
#include "experiments/output_set.h"
#include "experiments/study/study_merge.h"
#include "experiments/study/study_work.h"
#include "odometry/io/atomic_file.h"
#include "solvers/error.h"

namespace bivo::experiments::cli {

void print_study_output(const MergeOutput& output) {
  std::cout << output.markdown;
  if (output.report) std::cout << "\nreport: " << output.report->report_path << std::endl;
  std::cout << std::flush;
}

void finish_with_failures(const std::vector<std::string>& failures, int units, bool keep_going) {
  if (failures.empty()) return;
  for (const auto& f : failures) std::cerr << "failed: " << f << "\n";
  const std::string count = std::to_string(failures.size()) + " of " + std::to_string(units) +
                            " unit(s) failed; the others' outputs are written";
  if (!keep_going) throw Error(count + " (--keep-going: exit 0 all the same)");
  std::cerr << "bivo: " << count << " (--keep-going)" << std::endl;
}

void add_keep_going_flag(CLI::App* cmd, bool& keep_going) {
  cmd->add_flag("--keep-going", keep_going,
                "exit 0 even when some units failed (their cells say why; the count is still the last line)");
}

void add_study_command(CLI::App& app, const std::string& name, const std::string& description,
                       StudyFactory (*add_flags)(CLI::App*)) {
  auto* cmd = app.add_subcommand(name, description);
  const StudyFactory make = add_flags(cmd);
  auto keep_going = std::make_shared<bool>(false);
  add_keep_going_flag(cmd, *keep_going);
  cmd->callback([make, keep_going] {
    odometry::io::OutputJournal journal;  // a failed write takes the others back
    const MergeOutput out = run_study(make(), &std::cerr);
    journal.keep();
    print_study_output(out);
    finish_with_failures(out.failures, out.units, *keep_going);
  });
}

void add_merge_command(CLI::App& app) {
  struct Args {
    std::string study, results, output;
    bool partial = false, keep_going = false;
  };
  auto a = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("merge", "Check a study's result files and write the command's tables and plots");
  cmd->add_option("study", a->study, "study file written by `bivo plan`")->required()->check(CLI::ExistingFile);
  cmd->add_option("results", a->results, "folder of the result files (default: the study's name + .results)");
  cmd->add_option("--output", a->output, "output folder (default: the --output given to `bivo plan`)");
  cmd->add_flag("--partial", a->partial,
                "merge what is there: missing units become empty cells and notes, duplicates use the first file");
  add_keep_going_flag(cmd, a->keep_going);
  cmd->callback([a] {
    const Study study = read_study(a->study);
    const std::string results = a->results.empty() ? default_results_dir(a->study) : a->results;
    const std::string output = a->output.empty() ? study.output : a->output;
    std::vector<NamedPath> inputs = named_paths("a sequence of the study", study_sequences(study));
    inputs.push_back({"the study", a->study});
    inputs.push_back({"the results folder", results});
    check_output_folder({"--output", output}, inputs);
    const CollectedResults collected = collect_results(study, results);
    std::cerr << "merge: " << collected.files << " result file(s) in " << results << ": "
              << completeness_text(collected);
    if (!complete(collected) && !a->partial) {
      throw Error("merge: the results in '" + results +
                  "' are incomplete (see above); re-run the missing shards, "
                  "or merge what is there with --partial");
    }
    std::map<std::string, nlohmann::json> by_unit;
    for (const auto& [id, file] : collected.by_unit) by_unit[id] = file.result;
    odometry::io::OutputJournal journal;
    const MergeOutput out = merge_results(study, by_unit, output);
    journal.keep();
    print_study_output(out);
    finish_with_failures(out.failures, out.units, a->keep_going);
  });
}

}  // namespace bivo::experiments::cli
