// `bivo conic FILE`: solve a conic program (orthant x second-order cones) from a JSON file
// (format: experiments/conic_file.h, docs/conic.md) with the project's IPM.
#include <iostream>
#include <string>

#include "experiments/cli/commands.h"
#include "experiments/cli/flag_checks.h"
#include "experiments/conic_file.h"
#include "solvers/conic/ipm_solver.h"

namespace bivo::experiments::cli {

void add_conic_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("conic", "solve a conic program (orthant x SOC) from a JSON file with the own IPM");
  static std::string file;
  static solvers::conic::IpmSettings settings;
  static bool verbose = false, print_solution = false, no_polish = false;
  cmd->add_option("file", file, "JSON problem: c, A/b (optional), G, h, cones {l, q} (docs/conic.md)")->required();
  cmd->add_option("--feastol", settings.feastol, "primal/dual residual tolerance (relative)")->check(kFinitePositive);
  cmd->add_option("--abstol", settings.abstol, "absolute duality gap tolerance")->check(kFiniteNonNegative);
  cmd->add_option("--reltol", settings.reltol, "relative duality gap tolerance")->check(kFinitePositive);
  cmd->add_option("--max-iter", settings.max_iterations, "iteration limit")->check(CLI::PositiveNumber);
  cmd->add_option("--equilibration-passes", settings.equilibration_passes, "Ruiz passes (0 = off)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag("--no-polish", no_polish, "interior-point iterations only, no active-set Newton polish");
  cmd->add_flag("--verbose,-v", verbose, "per-iteration log");
  cmd->add_flag("--solution", print_solution, "also print x, y, z, s");
  cmd->callback([] {
    const auto p = read_conic_json(file);
    if (verbose) settings.log = &std::cout;
    settings.polish = !no_polish;
    std::cout << conic_result_text(solvers::conic::solve_conic(p, settings), print_solution) << std::flush;
  });
}

}  // namespace bivo::experiments::cli
