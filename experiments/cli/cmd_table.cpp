// `bivo table --sequences DIR... [--methods M...] --output DIR`: methods x sequences ->
// the paper's tables 1/2 (translational RPE m/s, best per column in bold) and table 3 (ms
// per pair), as Markdown + CSV + JSON (experiments/method_matrix.h). One work unit per
// method x sequence (experiments/study/study.h).
#include <memory>

#include "experiments/cli/commands.h"
#include "experiments/cli/tracker_flags.h"
#include "experiments/method_matrix.h"
#include "experiments/output_set.h"
#include "experiments/study/study_plan.h"
#include "odometry/odometry_methods.h"

namespace bivo::experiments::cli {

StudyFactory add_table_flags(CLI::App* cmd) {
  struct Args {
    std::shared_ptr<TrackerFlags> tracker;
    std::vector<std::string> sequences;
    std::vector<std::string> methods{"single", "tykkala", "weighted", "bounded"};
    std::string output;
    int first_frame = 0, max_frames = -1;
    double delta = 1.0;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("--sequences", a->sequences, "TUM sequence folders (columns)")->required();
  std::string names;
  for (const std::string& m : odometry::method_names()) names += (names.empty() ? "" : ", ") + m;
  cmd->add_option("--methods", a->methods, "methods (rows), each 'method' or 'method:backend'; methods: " + names)
      ->capture_default_str();
  cmd->add_option("--output", a->output, "folder for tables.md, rpe_trans.csv, runtime.csv, results.json, ...")
      ->required();
  cmd->add_option("--first-frame", a->first_frame, "first associated frame of every sequence")->capture_default_str();
  cmd->add_option("--max-frames", a->max_frames, "frames per sequence (-1: all)")->capture_default_str();
  cmd->add_option("--delta", a->delta, "RPE window [s] (a run spanning fewer than two gives \"too short\" cells)")
      ->capture_default_str()
      ->check(CLI::Range(1e-3, 1e6));
  a->tracker = std::make_shared<TrackerFlags>(cmd, false);
  return [a] {
    std::vector<NamedPath> inputs = named_paths("--sequences", a->sequences);
    inputs.push_back(a->tracker->config_input());
    check_output_folder({"--output", a->output}, inputs);
    MatrixOptions o;
    o.sequences = a->sequences;
    for (const auto& m : a->methods) o.methods.push_back(parse_method_spec(m));
    o.first_frame = a->first_frame;
    o.max_frames = a->max_frames;
    o.rpe_delta = a->delta;
    o.tracker = a->tracker->options();
    return table_study(o, a->output);
  };
}

void add_table_command(CLI::App& app) {
  add_study_command(app, "table", "Methods x sequences: RPE/ATE tables (paper tables 1/2) and runtimes (table 3)",
                    add_table_flags);
}

}  // namespace bivo::experiments::cli
