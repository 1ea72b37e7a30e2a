#pragma once
// Leave-one-sequence-out: a protocol that cannot tune on what it reports. A method with free
// parameters (e.g. robust's trust threshold) runs on every sequence at every setting, the
// cartesian product of the parameters' grids, the reference method (single) once per
// sequence; then for each held-out sequence the setting is chosen on all the OTHER sequences
// and only the held-out sequence's RPE at that setting is reported. Each run's score is its
// worst ratio to the reference, translational or rotational RPE; over the other sequences a
// setting has a worst score and a geometric mean. The settings whose worst is within
// LosoOptions::acceptable_ratio are acceptable (they never cost much); among them the smallest
// geometric mean (the largest typical gain) is chosen; when none is, the smallest worst (a
// tie: the geometric mean). Fixed methods (no grid) are
// reported beside it for comparison. With a CPU budget (LosoOptions::cost_budget) only the
// settings that keep within it on the other sequences are candidates. With pooled finest
// levels (LosoOptions::finest_levels) every run is made at each level, and the worst ratio,
// the geometric mean and the budget cover every level at once (each against the reference
// at the same level).
//
//   LosoOptions o;  o.sequences = {...};  o.method = "robust";
//   o.parameters = {{"trust", {30, 100, 300}}};  o.tracker.finest_level = 1;
//   LosoResult r = run_loso(o);  write_loso(r, "out/");
#include <string>
#include <vector>

#include "odometry/tracker.h"

namespace bivo::experiments {

struct LosoParameter {
  std::string name = "trust";  // a numeric tracker option (set_loso_parameter)
  std::vector<double> grid;    // its candidate values
};

struct LosoOptions {
  std::vector<std::string> sequences;
  std::string method = "robust";
  // Chosen together: the candidate settings are the cartesian product of the grids, the
  // first parameter's values varying slowest (loso_settings).
  std::vector<LosoParameter> parameters = {LosoParameter{}};
  std::string reference = "single";
  std::vector<std::string> methods;  // reported beside, at their defaults
  odometry::TrackerOptions tracker;  // every run starts from it
  // Pooled finest levels: every run is made at each (overriding tracker.finest_level) and
  // the choice covers them all; empty: tracker.finest_level alone.
  std::vector<int> finest_levels;
  int first_frame = 0, max_frames = -1;
  double rpe_delta = 1.0;  // RPE window [s]; every sequence must span two
  int progress = -1;
  // A CPU budget (0: none), for a speed setting: in each fold only the settings whose CPU per
  // pair over the other sequences (the geometric mean of the sequences' ratios of medians) is
  // at most cost_budget times cost_method's, at every finest level, are candidates, and
  // accuracy chooses among them as above; when none keeps within it, the cheapest (at its most
  // expensive level) is chosen. cost_method: the reference or one of `methods`.
  double cost_budget = 0.0;
  std::string cost_method = "weighted";
  // The worst ratio to the reference a setting may have on the other sequences and still be
  // chosen for its geometric mean (0: none may; the smallest worst ratio always decides).
  // Without it the rule prefers a value at which the method does nothing (ratio 1 on every
  // sequence) to one that gains on most and costs 2 % on one.
  double acceptable_ratio = 1.05;
};

// One run: a sequence with one method (at one setting when `values` is set) at one level.
struct LosoRun {
  int sequence = 0;
  std::string method;
  std::vector<double> values;  // the setting, one value per parameter; empty: reference or fixed method
  int finest_level = -1;       // with pooled finest levels, the run's; -1: tracker.finest_level
  bool ok = false;
  std::string sequence_name, error;
  double rpe_trans = 0.0, rpe_rot = 0.0;  // RMSE over LosoOptions::rpe_delta windows [m], [deg] per window
  double median_cpu_ms = 0.0;
  std::vector<double> pair_trans, pair_rot;  // per-pair errors against ground truth [m], [deg]
};

// One held-out sequence (with pooled finest levels: one row per level, sequence-major).
struct LosoRow {
  std::string sequence;
  int finest_level = -1;               // with pooled finest levels, the row's; -1 otherwise
  std::vector<double> chosen;          // the setting chosen without this sequence (per parameter)
  double train_worst = 0.0;            // its worst ratio over the other sequences (and every level)
  double train_mean = 0.0;             // the geometric mean of its per-sequence worst ratios there
  double train_cost = 0.0;             // with a cost budget: its CPU per pair there / cost_method's, at this level
  const LosoRun* reference = nullptr;  // this sequence's, at this level
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

// The candidate settings: the cartesian product of the parameters' grids, one value per
// parameter, the first parameter's varying slowest.
std::vector<std::vector<double>> loso_settings(const LosoOptions& options);

// The runs the protocol needs, in order: per sequence (and per pooled finest level) the
// reference, the settings, the methods; bivo::Error for options that cannot be held out
// (fewer than 2 sequences, no parameter, one given twice, an empty grid, a bad parameter or
// value, a finest level outside the pyramid or listed twice, a cost budget without its cost
// method among the runs).
std::vector<LosoRun> loso_units(const LosoOptions& options);
void run_loso_unit(const LosoOptions& options, LosoRun& run);
// The held-out rows from completed runs; bivo::Error when fewer than 2 sequences or a
// reference run failed (ratios undefined).
LosoResult assemble_loso(const LosoOptions& options, std::vector<LosoRun> runs);
LosoResult run_loso(const LosoOptions& options);

// loso.md (the held-out table), loso.csv (the same), runs.csv (every run) and pairs.csv
// (every pair's error of every run) into dir, atomically; returns the Markdown. One
// parameter's values are in columns "chosen" (loso.csv) and "value" (runs.csv, pairs.csv);
// several have a column each, "chosen:<name>" and "value:<name>". Pooled finest levels give
// a row per (held-out sequence, level) and a finest-level column in every file.
std::string write_loso(const LosoResult& result, const std::string& dir);

}  // namespace bivo::experiments
