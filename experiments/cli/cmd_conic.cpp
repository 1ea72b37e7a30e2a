// `bivo conic FILE`: solve a conic program (orthant x second-order cones) from a JSON file
// (format: experiments/conic_files/conic_file.h, docs/conic.md) or a CBF file (CBLIB's Conic Benchmark
// Format: experiments/conic_files/cbf_file.h) with the project's IPM.
#include <cstdio>
#include <iostream>
#include <new>
#include <string>

#include "experiments/cli/commands.h"
#include "experiments/cli/flag_checks.h"
#include "experiments/conic_files/cbf_file.h"
#include "experiments/conic_files/conic_file.h"
#include "solvers/conic/ipm_solver.h"

namespace bivo::experiments::cli {

void add_conic_command(CLI::App& app) {
  auto* cmd =
      app.add_subcommand("conic", "solve a conic program (orthant x SOC) from a JSON or CBF file with the own IPM");
  static std::string file, format = "auto";
  static solvers::conic::IpmSettings settings;
  static bool verbose = false, print_solution = false, no_polish = false;
  cmd->add_option("file", file, "JSON problem (c, A/b, G, h, cones {l, q}; docs/conic.md) or CBF file (*.cbf)")
      ->required();
  cmd->add_option("--format", format, "auto (by extension: .cbf = CBF, else JSON), json or cbf")
      ->check(CLI::IsMember({"auto", "json", "cbf"}))
      ->capture_default_str();
  cmd->add_option("--feastol", settings.feastol, "primal/dual residual tolerance (relative)")->check(kFinitePositive);
  cmd->add_option("--abstol", settings.abstol, "absolute duality gap tolerance")->check(kFiniteNonNegative);
  cmd->add_option("--reltol", settings.reltol, "relative duality gap tolerance")->check(kFinitePositive);
  cmd->add_option("--gaptol", settings.gaptol, "relative objective gap |c'x + b'y + h'z| / (1 + |c'x|) tolerance")
      ->check(kFinitePositive);
  cmd->add_option("--infinity", settings.infinity,
                  "bounds at or beyond this are absent: orthant rows with h >= it, SOCs with head h >= it are removed")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--max-iter", settings.max_iterations, "iteration limit")->check(CLI::PositiveNumber);
  cmd->add_option("--equilibration-passes", settings.equilibration_passes, "Ruiz passes (0 = off)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag("--no-polish", no_polish, "interior-point iterations only, no active-set Newton polish");
  cmd->add_flag("--verbose,-v", verbose, "per-iteration log and the time by phase");
  cmd->add_flag("--solution", print_solution, "also print x, y, z, s");
  cmd->callback([] {
    const bool cbf = format == "cbf" || (format == "auto" && is_cbf_path(file));
    CbfProblem problem;
    solvers::conic::IpmResult r;
    // Sizes up to --max-conic-size are accepted; whether they fit in this machine's memory
    // is only known when allocating.
    try {
      if (cbf)
        problem = read_cbf(file);
      else
        problem.problem = read_conic_json(file);
      if (verbose) settings.log = &std::cout;
      settings.time_phases = verbose;
      settings.polish = !no_polish;
      r = solvers::conic::solve_conic(problem.problem, settings);
    } catch (const std::bad_alloc&) {
      throw Error("conic: the problem in '" + file + "' does not fit in memory (--max-conic-size " +
                  std::to_string(max_cbf_size()) + " admits it; lower it to refuse such files up front)");
    }
    std::cout << conic_result_text(r, print_solution);
    if (!r.note.empty()) std::cout << "note: " << r.note << "\n";
    if (cbf && r.status == solvers::conic::IpmStatus::kOptimal) {
      std::printf("file objective (%s, constant included): %.12g\n", problem.maximize ? "max" : "min",
                  problem.file_objective(r.primal_objective));
    }
    if (verbose) std::cout << r.timings.text(r.iterations);
    std::cout << std::flush;
  });
}

}  // namespace bivo::experiments::cli
