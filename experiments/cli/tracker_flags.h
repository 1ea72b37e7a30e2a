#pragma once
// One command-line flag per tracker option of the table (experiments/tracker_option_table.h),
// plus `--config FILE.json` (experiments/tracker_config.h), for every subcommand that runs the
// tracker. The effective options are: the defaults, then the --config file (if given), then
// every flag that was given on the command line, so `--config run.json --levels 3` changes one
// field. A flag's value is checked by the same code, with the same message, as the file's.
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "experiments/output_set.h"
#include "experiments/tracker_option_table.h"
#include "odometry/tracker.h"

namespace bivo::experiments::cli {

class TrackerFlags {
 public:
  // Adds the flags to `cmd`. With `with_method`, also --method and --backend and the
  // per-method parameters (refused with another method: --lambda only with fixed, ...).
  // `with_backend` adds --backend alone (commands that choose their methods themselves).
  TrackerFlags(CLI::App* cmd, bool with_method, bool with_backend = false);

  // After parsing. Throws bivo::Error on a bad config file, a flag's bad value ("--nu:
  // problem.weights.nu: -2 is outside (0, inf]") or a flag that does not apply to the method.
  odometry::TrackerOptions options() const;
  // The --config path ("" when not given).
  const std::string& config_path() const { return *config_; }
  NamedPath config_input() const { return {"--config", *config_}; }

 private:
  struct Flag {
    const TrackerOption* option;
    CLI::Option* cli;
    std::shared_ptr<std::string> text;
  };

  bool with_method_;
  std::shared_ptr<std::string> config_ = std::make_shared<std::string>();
  std::vector<Flag> flags_;
};

}  // namespace bivo::experiments::cli
