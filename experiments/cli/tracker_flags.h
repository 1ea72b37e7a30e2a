#pragma once
// One command-line flag per odometry::TrackerOptions field, plus `--config FILE.json`
// (experiments/tracker_config.h), for every subcommand that runs the tracker. The effective
// options are: the defaults, then the --config file (if given), then every flag that was
// given on the command line, so `--config run.json --levels 3` changes one field.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "odometry/tracker.h"

namespace bivo::experiments::cli {

class TrackerFlags {
 public:
  // Adds the flags to `cmd`. With `with_method`, also --method and --backend and the
  // per-method parameters' consistency checks (--lambda only with fixed, ...).
  TrackerFlags(CLI::App* cmd, bool with_method);

  // After parsing. Throws bivo::Error on a bad config file or a flag that does not apply to
  // the method (naming both).
  odometry::TrackerOptions options() const;
  // The --config path ("" when not given).
  const std::string& config_path() const { return *config_; }

 private:
  struct Flag {
    CLI::Option* option;
    std::function<void(odometry::TrackerOptions&)> apply;
  };
  template <class T>
  CLI::Option* add(const std::string& name, const std::string& help, T initial,
                   std::function<void(odometry::TrackerOptions&, const T&)> set);

  CLI::App* cmd_;
  bool with_method_;
  std::shared_ptr<std::string> config_ = std::make_shared<std::string>();
  std::vector<Flag> flags_;
  CLI::Option *method_ = nullptr, *lambda_ = nullptr, *eps_ = nullptr, *phi_ = nullptr, *delta_ = nullptr, *eps_min_ = nullptr,
              *eps_max_ = nullptr, *kappa_ = nullptr, *eps_ratio_ = nullptr, *guard_ = nullptr, *trust_ = nullptr,
              *joint_tolerance_ = nullptr, *relaxed_tolerance_ = nullptr;
};

}  // namespace bivo::experiments::cli
