#pragma once
// Each `bivo` subcommand lives in its own file experiments/cli/cmd_<name>.cpp and adds itself
// to the CLI11 app here. Handlers throw bivo::Error on bad input; main prints it and exits 1.
#include <CLI/CLI.hpp>

namespace bivo::experiments::cli {

void add_run_command(CLI::App& app);
void add_eval_command(CLI::App& app);
void add_synth_command(CLI::App& app);
void add_table_command(CLI::App& app);
void add_sweep_command(CLI::App& app);
void add_pareto_command(CLI::App& app);
void add_profile_command(CLI::App& app);
void add_report_command(CLI::App& app);
void add_demo_command(CLI::App& app);
void add_conic_command(CLI::App& app);

}  // namespace bivo::experiments::cli
