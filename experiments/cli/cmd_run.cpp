// `bivo run SEQUENCE_DIR --method M [--backend B] ...`: frame-to-frame odometry over one TUM
// sequence; writes the TUM trajectory, a per-pair log and the effective configuration, ends
// stdout with the run line
// "frames=N median_ms=X mean_ms=Y median_cpu_ms=A mean_cpu_ms=B failures=K".
#include <filesystem>
#include <iostream>
#include <memory>

#include "experiments/cli/commands.h"
#include "experiments/cli/tracker_flags.h"
#include "experiments/sequence_runner.h"
#include "experiments/tracker_option_table.h"
#include "solvers/error.h"

namespace bivo::experiments::cli {

namespace {

// The configuration file written beside a trajectory: est.txt -> est.config.json.
std::string config_path_for(const std::string& output) {
  return std::filesystem::path(output).replace_extension(".config.json").string();
}

}  // namespace

void add_run_command(CLI::App& app) {
  struct Args {
    RunRequest request;
    std::string output, log, save_config;
    std::unique_ptr<TrackerFlags> tracker;
  };
  auto a = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("run", "Frame-to-frame RGB-D odometry over one TUM sequence");
  cmd->add_option("sequence", a->request.sequence_dir,
                  "TUM sequence folder (rgb.txt + depth.txt or associations.txt; groundtruth.txt optional)")
      ->required();
  a->tracker = std::make_unique<TrackerFlags>(cmd, true);
  auto* first =
      cmd->add_option("--first-frame", a->request.first_frame, "index of the first associated frame to process")
          ->capture_default_str();
  auto* max = cmd->add_option("--max-frames", a->request.max_frames, "process at most N frames (-1: all)")
                  ->capture_default_str();
  cmd->add_option("--output", a->output,
                  "estimated trajectory (TUM format, one pose per processed frame); the effective configuration "
                  "is written beside it as <output stem>.config.json");
  cmd->add_option("--log", a->log, "per-pair CSV (timings, lambda/epsilon, objectives, errors vs ground truth)");
  cmd->add_option("--save-config", a->save_config,
                  "also write the effective configuration (JSON, for --config) to this file");
  cmd->footer(
      "Ends stdout with: frames=N median_ms=X mean_ms=Y median_cpu_ms=A mean_cpu_ms=B failures=K (wall and CPU "
      "time per pair, loading excluded).");
  cmd->callback([a, first, max] {
    RunRequest req = a->request;
    req.tracker = a->tracker->options();
    // The frame window is part of the configuration: flags win over the file.
    if (first->count() > 0) req.tracker.first_frame = req.first_frame;
    if (max->count() > 0) req.tracker.max_frames = req.max_frames;
    req.first_frame = req.tracker.first_frame;
    req.max_frames = req.tracker.max_frames;
    // The log reports both objectives of every method (single / depth optimize one).
    if (!a->log.empty()) req.tracker.evaluate_unused_objective = true;
    // Fail before the run, not after it, when an output cannot be written.
    const std::string config_beside = a->output.empty() ? "" : config_path_for(a->output);
    req.opened = open_run_sequence(req);  // read once, for the output check and the run
    std::vector<NamedPath> inputs = run_input_files(req);
    inputs.push_back({"--config", a->tracker->config_path()});
    const RunOutputPaths outputs{a->output, a->log, {config_beside, a->save_config}};
    check_output_files({{"--output", a->output},
                        {"--log", a->log},
                        {"the configuration beside --output", config_beside},
                        {"--save-config", a->save_config}},
                       inputs);
    const RunOutcome run = run_sequence(req);
    write_run_outputs(run, req.tracker, outputs);
    if (req.tracker.readout_time < 0.0 && run.readout_time > 0.0) {
      std::cout << "note: colour images unrolled with the " << format_option_number(run.readout_time)
                << " s rolling-shutter readout the sequence states (scene.json); --readout-time 0: global shutter\n";
    }
    if (req.tracker.vignetting < 0.0 && run.vignetting > 0.0) {
      std::cout << "note: colour fall-off 1 - " << format_option_number(run.vignetting)
                << " rho^2 the sequence states (scene.json) divided out; --vignetting 0: frames as taken\n";
    }
    std::cout << run_summary_line(run) << std::endl;
  });
}

}  // namespace bivo::experiments::cli
