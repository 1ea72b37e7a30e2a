#pragma once
// One Markdown report over a set of sequences: the methods x sequences tables (paper tables
// 1-3), per-frame translational error (fig. 5), lambda / epsilon sweeps (fig. 3), one Pareto
// front per sequence, runtime bars; CSV/JSON beside every plot. Used by `bivo report` and
// `bivo demo`.
//
// Layout of the output folder:
//   report.md, tables/ (method_matrix outputs), sweep/ (sweep.csv, ...), pareto/ (JSON),
//   images/ (PNG), trajectories/ (estimated TUM trajectories).
#include <optional>
#include <string>
#include <vector>

#include "experiments/method_matrix.h"
#include "experiments/parameter_sweep.h"
#include "experiments/pareto_study.h"

namespace bivo::experiments {

struct ReportOptions {
  std::string title = "bivo report";
  std::vector<std::string> sequences;
  std::vector<MethodSpec> methods;
  odometry::TrackerOptions tracker;
  int first_frame = 0, max_frames = -1;  // for the method tables
  double rpe_delta = 1.0;                // RPE window [s] of the tables and sweeps
  // Sweeps: grids (empty: no sweep) and the frames each sweep run processes.
  std::vector<double> lambdas, epsilons;
  int sweep_max_frames = 60;
  // Pareto: one pair per sequence (the middle of the processed window) at this level.
  bool pareto = true;
  int pareto_level = 1, pareto_points = 15;
  bool plots = true;
  int progress = -1;
  std::string preamble;  // Markdown inserted after the title (e.g. how the data was made)
};

struct ReportResult {
  MethodMatrix matrix;
  std::string tables_markdown;
  std::string report_path;
  std::vector<std::string> images;  // paths of the PNGs written
};

// The Pareto part of a report: one study per sequence (the middle pair of its window), or
// why there is none.
struct ReportPareto {
  std::string sequence;  // column label (sequence_label)
  std::optional<ParetoStudy> study;
  std::string error;
};

// What the report's work units produced (study.h runs them, in one process or as shards).
struct ReportParts {
  MethodMatrix matrix;
  std::optional<SweepResult> sweep;  // absent: no grid, or no sequence with ground truth
  std::vector<ReportPareto> pareto;  // empty when options.pareto is false
};

// Writes the report folder from its parts (tables, sweep, Pareto JSON, plots, report.md,
// config.json); no tracking is done here.
ReportResult write_report(const ReportOptions& options, const ReportParts& parts, const std::string& output_dir);

// The whole report in one process: report_study (study_plan.h), every unit (one line per
// unit on stderr), write_report.
ReportResult build_report(const ReportOptions& options, const std::string& output_dir);

}  // namespace bivo::experiments
