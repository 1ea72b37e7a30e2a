#pragma once
// Leave-one-sequence-out: a protocol that cannot tune on what it reports. A method with one
// free parameter (e.g. robust's trust threshold) runs on every sequence at every grid value,
// the reference method (single) once per sequence; then for each held-out sequence the value
// is chosen on all the OTHER sequences (the smallest worst ratio to the reference over them,
// translational and rotational RPE alike; on a tie, the smallest geometric mean of those
// per-sequence worst ratios) and only the held-out sequence's RPE at that value is reported. Fixed methods (no grid)
// are reported beside it for comparison. With a CPU budget (LosoOptions::cost_budget) only the
// values that keep within it on the other sequences are candidates.
//
//   LosoOptions o;  o.sequences = {...};  o.method = "robust";  o.parameter = "trust";
//   o.grid = {30, 100, 300};  o.tracker.finest_level = 1;
//   LosoResult r = run_loso(o);  write_loso(r, "out/");
#include <string>
#include <vector>

#include "odometry/tracker.h"

namespace bivo::experiments {

struct LosoOptions {
  std::vector<std::string> sequences;
  std::string method = "robust";
  std::string parameter = "trust";  // a numeric tracker option (set_loso_parameter)
  std::vector<double> grid;
  std::string reference = "single";
  std::vector<std::string> methods;  // reported beside, at their defaults
  odometry::TrackerOptions tracker;  // every run starts from it
  int first_frame = 0, max_frames = -1;
  int progress = -1;
  // A CPU budget (0: none), for a speed setting: in each fold only the values whose CPU per
  // pair over the other sequences (the sum of each sequence's median) is at most cost_budget
  // times cost_method's are candidates, and accuracy chooses among them as above; when no
  // value keeps within it, the cheapest is chosen. cost_method: the reference or one of
  // `methods`.
  double cost_budget = 0.0;
  std::string cost_method = "weighted";
};

// One run: a sequence with one method (at one grid value when `value` is set).
struct LosoRun {
  int sequence = 0;
  std::string method;
  bool has_value = false;
  double value = 0.0;
  bool ok = false;
  std::string sequence_name, error;
  double rpe_trans = 0.0, rpe_rot = 0.0;  // RMSE over 1-s windows [m/s], [deg/s]
  double median_cpu_ms = 0.0;
  std::vector<double> pair_trans, pair_rot;  // per-pair errors against ground truth [m], [deg]
};

struct LosoRow {
  std::string sequence;
  double chosen = 0.0;       // value chosen without this sequence
  double train_worst = 0.0;  // its worst ratio over the other sequences
  double train_cost = 0.0;   // with a cost budget: its CPU per pair there / cost_method's
  const LosoRun* reference = nullptr;
  const LosoRun* held_out = nullptr;   // the method at `chosen` on this sequence
  std::vector<const LosoRun*> others;  // the fixed methods, LosoOptions::methods order
};

struct LosoResult {
  LosoOptions options;
  std::vector<LosoRun> runs;
  std::vector<LosoRow> rows;
};

// Sets the numeric tracker option `name`, a JSON key of tracker_option_table.h
// ("problem.depth_noise_exponent", "policy.trust"; a policy key also without "policy."),
// checked as a flag or a configuration file would be; bivo::Error naming the valid keys or
// the value's range otherwise.
void set_loso_parameter(odometry::TrackerOptions& options, const std::string& name, double value);

// The runs the protocol needs, in order: per sequence the reference, the grid, the methods;
// bivo::Error for options that cannot be held out (fewer than 2 sequences, an empty grid, a
// bad parameter or value, a cost budget without its cost method among the runs).
std::vector<LosoRun> loso_units(const LosoOptions& options);
void run_loso_unit(const LosoOptions& options, LosoRun& run);
// The held-out rows from completed runs; bivo::Error when fewer than 2 sequences or a
// reference run failed (ratios undefined).
LosoResult assemble_loso(const LosoOptions& options, std::vector<LosoRun> runs);
LosoResult run_loso(const LosoOptions& options);

// loso.md (the held-out table), loso.csv (the same), runs.csv (every run) and pairs.csv
// (every pair's error of every run) into dir, atomically; returns the Markdown.
std::string write_loso(const LosoResult& result, const std::string& dir);

}  // namespace bivo::experiments
