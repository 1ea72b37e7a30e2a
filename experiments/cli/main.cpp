// The `bivo` command line: one CLI11 app, one subcommand per experiments/cli/cmd_*.cpp.
#include <cstdint>
#include <exception>
#include <filesystem>
#include <iostream>
#include <new>
#include <string>

#include <CLI/CLI.hpp>

#include "experiments/cli/commands.h"
#include "experiments/conic_files/cbf_file.h"
#include "odometry/io/atomic_file.h"
#include "odometry/io/input_limits.h"
#include "solvers/error.h"

namespace {

// "filesystem error: cannot create directories: <cause> [<path>]" -> "create directories".
std::string fs_operation(const std::filesystem::filesystem_error& e) {
  std::string what = e.what();
  const std::string head = "filesystem error: cannot ";
  if (what.rfind(head, 0) != 0) return "access";
  what = what.substr(head.size());
  return what.substr(0, what.find(':'));
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"bivo: a testbed for bi-objective optimization, flagship instance RGB-D odometry"};
  app.require_subcommand(1);
  // Input limits (odometry/io/input_limits.h), before or after the subcommand.
  auto& limits = bivo::odometry::io::input_limits();
  app.add_option("--max-image-pixels", limits.max_image_pixels, "largest image (width x height) read or rendered")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--max-list-entries", limits.max_list_entries,
                 "most lines of a TUM list or trajectory (and frames of a rendered sequence)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--max-conic-size", bivo::experiments::max_cbf_size(),
                 "most variables + constraints a CBF file may declare (at most 2^30)")
      ->capture_default_str()
      ->check(CLI::Range(std::int64_t{1}, std::int64_t{1} << 30));
  app.fallthrough();
  const bivo::odometry::io::InputRegistry inputs;  // no output of this run replaces a file it read
  namespace ex = bivo::experiments::cli;
  ex::add_demo_command(app);
  ex::add_run_command(app);
  ex::add_eval_command(app);
  ex::add_synth_command(app);
  ex::add_depth_stats_command(app);
  ex::add_table_command(app);
  ex::add_sweep_command(app);
  ex::add_pareto_command(app);
  ex::add_profile_command(app);
  ex::add_report_command(app);
  ex::add_conic_command(app);
  ex::add_plan_command(app);
  ex::add_work_command(app);
  ex::add_merge_command(app);
  ex::add_loso_command(app);
  // Exit codes (README, "Outcomes and exit codes"): 0 when every unit produced its result; 2
  // for a command line of the wrong shape (unknown command or flag, a required argument or a
  // value missing, flags that exclude each other); 1 for every other error, including a value
  // a flag refuses (out of range, not a number, no such file), as the same value in a
  // configuration or study file is.
  try {
    app.parse(argc, argv);
  } catch (const CLI::ValidationError& e) {
    std::cerr << "bivo: error: " << e.what() << "\n";
    return 1;
  } catch (const CLI::ConversionError& e) {
    std::cerr << "bivo: error: " << e.what() << "\n";
    return 1;
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints the message (or the --help text, code 0)
    return code == 0 ? 0 : 2;
  } catch (const bivo::Error& e) {
    std::cerr << "bivo: error: " << e.what() << "\n";
    return 1;
  } catch (const std::filesystem::filesystem_error& e) {
    // A folder or file the system refused (read-only, permissions, a file in the way): the
    // operation, the path and the cause, as any other error.
    std::cerr << "bivo: error: cannot " << fs_operation(e) << " '" << e.path1().string() << "': " << e.code().message()
              << "\n";
    return 1;
  } catch (const std::bad_alloc&) {
    std::cerr << "bivo: error: out of memory (an input larger than this machine holds? see the --max-* limits)\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "bivo: internal error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
