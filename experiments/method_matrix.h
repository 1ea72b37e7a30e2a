#pragma once
// Methods x sequences: every method run over every sequence, evaluated against ground truth
// (TUM RPE over 1-s windows, ATE), and written out as the paper's tables 1/2 (RPE m/s, best
// per column in bold) and table 3 (ms per pair), Markdown + CSV + JSON, plus the long-format
// per-pair CSV the plots read. Used by `bivo table`, `bivo report` and `bivo demo`.
#include <optional>
#include <string>
#include <vector>

#include "experiments/sequence_runner.h"
#include "odometry/io/metrics.h"

namespace bivo::experiments {

struct MethodSpec {
  std::string method;
  std::string backend;  // empty: the method's default
};

// "bounded" or "bounded:ipm-full" -> {method, backend}; validated by the tracker later.
MethodSpec parse_method_spec(const std::string& text);
std::string label(const MethodSpec& spec);  // "bounded" or "bounded (ipm-full)"

struct MatrixOptions {
  std::vector<std::string> sequences;  // TUM folders
  std::vector<MethodSpec> methods;
  odometry::TrackerOptions tracker;  // method/backend overwritten per cell
  int first_frame = 0, max_frames = -1;
  int progress = -1;
  std::string trajectory_dir;  // when set: <dir>/<sequence>__<method>.txt
  double rpe_delta = 1.0;      // RPE window [s]
};

struct MatrixCell {
  std::string sequence_dir, sequence;
  MethodSpec spec;
  std::string backend;  // effective
  std::optional<RunOutcome> run;
  std::optional<odometry::io::RpeResult> rpe;
  std::optional<odometry::io::AteResult> ate;
  std::string note;  // why rpe/ate/run is missing
};

struct MethodMatrix {
  std::vector<std::string> sequences;  // sequence_labels, column order
  std::vector<MethodSpec> methods;     // row order
  std::vector<MatrixCell> cells;       // row-major: methods x sequences
  double rpe_delta = 1.0;              // RPE window [s] of every cell
  const MatrixCell& at(int method, int sequence) const { return cells[method * sequences.size() + sequence]; }
};

// The column header of a sequence folder: its name without the "rgbd_dataset_" prefix.
std::string sequence_label(const std::string& sequence_dir);
// The column headers of a list of sequence folders, one per folder and all distinct, so no
// two results share a column or an output file: sequence_label, and for folders whose labels
// coincide (two seeds rendered as syn1/x and syn2/x) "label~" plus 6 hex digits of a hash of
// the absolute path (and "#position" for a folder given twice).
std::vector<std::string> sequence_labels(const std::vector<std::string>& sequence_dirs);

// Throws bivo::Error when there are no sequences or methods, or a method/backend is bad
// (checked for every method before anything runs).
void check_matrix_options(const MatrixOptions& options);

// One work unit of the matrix: options.methods[method] on options.sequences[sequence]. A run
// that throws bivo::Error (e.g. a method that cannot process a sequence) is recorded in the
// cell's note. Writes nothing (trajectory_dir is not used).
MatrixCell run_matrix_cell(const MatrixOptions& options, int method, int sequence);

// The matrix from its cells in row-major order (methods x sequences); throws bivo::Error
// when the count does not match.
MethodMatrix assemble_matrix(const MatrixOptions& options, std::vector<MatrixCell> cells);

// <dir>/<sequence>__<method>[-<backend>].txt for every cell that ran (created when missing).
void write_matrix_trajectories(const MethodMatrix& matrix, const std::string& dir);

// Every cell in one process (the study layer, study.h, runs the same cells as shards):
// check_matrix_options, run_matrix_cell for each, assemble_matrix, and the trajectories
// when options.trajectory_dir is set.
MethodMatrix run_matrix(const MatrixOptions& options);

// Writes into `dir` (created when missing): rpe_trans.{md,csv}, rpe_rot.csv, ate.csv,
// runtime.{md,csv} (ms per pair, median over pairs), runtime_bars.csv (one row per method,
// median/mean over all pairs of all sequences), pairs.csv (sequence,method,pair,t,
// trans_err_m,rot_err_deg,ms,lambda,epsilon_per_weight,iterations) and results.json. Every
// file is written atomically. Returns the Markdown of the tables.
std::string write_matrix(const MethodMatrix& matrix, const std::string& dir);

// Markdown tables alone (RPE trans, RPE rot, ATE, runtime), as in the report.
std::string matrix_markdown(const MethodMatrix& matrix);

}  // namespace bivo::experiments
