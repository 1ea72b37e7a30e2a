#pragma once
// Each `bivo` subcommand lives in its own file experiments/cli/cmd_<name>.cpp and adds itself
// to the CLI11 app here. Handlers throw bivo::Error on bad input; main prints it and exits 1.
#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "experiments/study/study.h"
#include "experiments/study/study_merge.h"

namespace bivo::experiments::cli {

void add_run_command(CLI::App& app);
void add_eval_command(CLI::App& app);
void add_synth_command(CLI::App& app);
void add_depth_stats_command(CLI::App& app);
void add_table_command(CLI::App& app);
void add_sweep_command(CLI::App& app);
void add_pareto_command(CLI::App& app);
void add_profile_command(CLI::App& app);
void add_report_command(CLI::App& app);
void add_demo_command(CLI::App& app);
void add_conic_command(CLI::App& app);
void add_plan_command(CLI::App& app);
void add_work_command(CLI::App& app);
void add_merge_command(CLI::App& app);
void add_loso_command(CLI::App& app);

// The flags of a study command (table, sweep, pareto, report, loso), shared by the command itself
// and by `bivo plan KIND`: add_<kind>_flags adds them to `cmd` and returns the function that
// builds the study from the parsed values (study_plan.h). The command = that study run in
// one process (run_study); `bivo plan` writes it for `bivo work` / `bivo merge` instead.
using StudyFactory = std::function<Study()>;
StudyFactory add_table_flags(CLI::App* cmd);
StudyFactory add_sweep_flags(CLI::App* cmd);
StudyFactory add_pareto_flags(CLI::App* cmd);
StudyFactory add_report_flags(CLI::App* cmd);
StudyFactory add_loso_flags(CLI::App* cmd);

// Adds `bivo NAME` with the flags of add_flags: the study run in this process, then what
// the command prints (cmd_merge.cpp).
void add_study_command(CLI::App& app, const std::string& name, const std::string& description,
                       StudyFactory (*add_flags)(CLI::App*));
// What a study's command prints on stdout once its outputs are written.
void print_study_output(const MergeOutput& output);
// After the outputs are written: lists the failed units on stderr and, unless keep_going,
// throws bivo::Error counting them (exit 1); with keep_going the count is the last line.
void finish_with_failures(const std::vector<std::string>& failures, int units, bool keep_going);
void add_keep_going_flag(CLI::App* cmd, bool& keep_going);

}  // namespace bivo::experiments::cli
