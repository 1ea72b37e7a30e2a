// `bivo profile SEQUENCE_DIR [--methods M[:B]...] --output DIR`: time per phase, iterations
// per level and the epsilon-constraint vs Gauss-Newton gap per level
// (experiments/profile_study.h).
#include <iostream>
#include <memory>

#include "experiments/cli/commands.h"
#include "experiments/cli/tracker_flags.h"
#include "experiments/output_set.h"
#include "experiments/profile_study.h"
#include "experiments/tracker_config.h"

namespace bivo::experiments::cli {

void add_profile_command(CLI::App& app) {
  struct Args {
    std::shared_ptr<TrackerFlags> tracker;
    ProfileOptions o;
    std::vector<std::string> methods{"single:gn",     "single:lm",        "single:ceres",          "weighted:gn",
                                     "bounded:exact", "bounded:ipm-full", "bounded:ipm-compressed"};
    std::string output;
    bool keep_going = false;
  };
  auto a = std::make_shared<Args>();
  auto* cmd =
      app.add_subcommand("profile", "Time per phase, iterations per level and the QCQP/SOCP vs Gauss-Newton gap");
  cmd->add_option("sequence", a->o.sequence_dir, "TUM sequence folder")->required();
  cmd->add_option("--methods", a->methods, "'method:backend' entries (single:gn is the reference)")
      ->capture_default_str();
  cmd->add_option("--first-frame", a->o.first_frame, "first associated frame")->capture_default_str();
  cmd->add_option("--max-frames", a->o.max_frames, "frames per run")->capture_default_str();
  cmd->add_option("--socp-max-frames", a->o.socp_max_frames,
                  "frames for the interior-point SOCP backends (bounded:ipm-*; seconds per pair; 0 = --max-frames)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--repetitions", a->o.repetitions,
                  "timed runs of every method (after one untimed warm-up), interleaved; medians and quartiles")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  a->tracker = std::make_shared<TrackerFlags>(cmd, false);
  cmd->add_option("--output", a->output, "folder for profile.md / .csv / .json")->required();
  add_keep_going_flag(cmd, a->keep_going);
  cmd->callback([a] {
    check_output_folder({"--output", a->output}, {{"sequence", a->o.sequence_dir}, a->tracker->config_input()});
    ProfileOptions o = a->o;
    for (const auto& m : a->methods) o.methods.push_back(parse_method_spec(m));
    o.tracker = a->tracker->options();
    const std::vector<ProfileRow> rows = run_profile(o);
    std::cout << write_profile(rows, a->output);
    write_tracker_config(a->output + "/config.json", o.tracker);
    // A method whose runs failed is a row of zeros with its note: not a profile to exit 0 on.
    std::vector<std::string> failures;
    for (const ProfileRow& r : rows) {
      if (!r.note.empty()) failures.push_back(r.method + " (" + r.backend + "): " + r.note);
    }
    finish_with_failures(failures, static_cast<int>(rows.size()), a->keep_going);
  });
}

}  // namespace bivo::experiments::cli
