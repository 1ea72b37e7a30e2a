#pragma once
// One description of an experiment — a study — that `bivo table`, `sweep`, `pareto`,
// `report` and `loso` run in one process and that `bivo plan` / `work` / `merge` split into shards
// (docs/scaling.md). A study is a list of independent work units:
//   table:  one per method x sequence (method_matrix.h, run_matrix_cell)
//   sweep:  one per sequence x {single reference, each lambda, each epsilon} (sweep_units)
//   pareto: one per frame pair (run_pareto_study)
//   report: the units of its table, its sweep and its Pareto pairs
//   loso:   one per sequence x finest level x {reference, each setting, each fixed method}
//           (loso_units; a setting: one value per parameter, the product of their grids)
// The engines run a unit and assemble their tables from unit results; this file only
// describes, names and deals out the units.
//
// The study file (JSON) is strict like tracker_config.h (an unknown key is an error naming
// its path); the tracker options are tracker_config's JSON, bit-exact:
//   {"format": "bivo-study", "version": 1, "kind": "report", "output": "/abs/report",
//    "study_hash": "<study_hash>" (required: edits after planning are refused),
//    "seed": 1, "plots": true, "tracker": {...tracker_config...},
//    "table": {"sequences": [...], "methods": ["single", "bounded:ipm-full"],
//              "first_frame": 0, "max_frames": -1},
//    "sweep": {"sequences": [...], "lambdas": [...], "epsilons": [...], "epsilon_backend": "",
//              "first_frame": 0, "max_frames": 60},
//    "pareto": {"level": 1, "points": 15, "lambda_min": 1, "lambda_max": 1e7,
//               "methods": [...], "pairs": [{"sequence": "/abs/seq", "pair": 44}]},
//    "report": {"title": "...", "preamble": "..."},
//    "loso": {"sequences": [...], "method": "robust", "parameter": "trust", "grid": [...],
//             "reference": "single", "methods": [...], "first_frame": 0, "max_frames": -1}}
//   (loso with several parameters: "parameters": [{"parameter": ..., "grid": [...]}, ...] in
//   place of "parameter" and "grid"; with pooled finest levels "finest_levels": [0, 1]; with a
//   cost budget "cost_budget" and "cost_method"; "acceptable_ratio", absent: 0; none of the
//   three hashed: they choose among finished runs)
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "experiments/loso.h"
#include "experiments/method_matrix.h"
#include "experiments/parameter_sweep.h"
#include "experiments/pareto_study.h"
#include "odometry/tracker.h"

namespace bivo::experiments {

struct ParetoPairSpec {
  std::string sequence_dir;
  int pair = 0;  // reference frame; current = pair + 1
};

// The Pareto part: the options of every pair's study (sequence_dir and pair are taken from
// `pairs`) and the pairs.
struct ParetoPlan {
  ParetoStudyOptions options;
  std::vector<ParetoPairSpec> pairs;
};

struct ReportText {
  std::string title, preamble;
};

struct Study {
  std::string kind;    // "table", "sweep", "pareto", "report" or "loso"
  std::string output;  // the folder `bivo merge` writes (absolute)
  // Seeds the order in which units are dealt to shards; results never depend on it.
  std::uint64_t seed = 1;
  bool plots = true;  // pareto, report: PNGs beside the JSON
  // The tracker every run starts from (methods, grids and levels override per unit). The
  // parts' own `tracker` fields are not stored: study_units() and run_unit() use this one.
  odometry::TrackerOptions tracker;
  std::optional<MatrixOptions> table;  // table, report
  std::optional<SweepOptions> sweep;   // sweep; report when it has a grid (sequences may be empty)
  std::optional<ParetoPlan> pareto;    // pareto; report unless --no-pareto
  std::optional<ReportText> report;    // report
  std::optional<LosoOptions> loso;     // loso (its tracker and progress are not stored)
};

// Throws bivo::Error when the kind does not match its parts or a part is unusable (no
// sequences, a bad method or backend, an empty grid, a parameter that is no numeric tracker
// option or a grid value outside its range).
void check_study(const Study& study);

// Every sequence folder the study reads, in part order (repeats possible).
std::vector<std::string> study_sequences(const Study& study);

// "bounded:ipm-full" / "single": the inverse of parse_method_spec.
std::string method_spec_text(const MethodSpec& spec);

nlohmann::json study_to_json(const Study& study);
// `where` names the source in errors ("study.json").
Study study_from_json(const nlohmann::json& j, const std::string& where);
Study read_study(const std::string& path);
void write_study(const std::string& path, const Study& study);  // atomic, pretty-printed

// 16 hex digits (64-bit FNV-1a) of the canonical JSON of what the units compute: kind,
// tracker and parts — not output, plots, seed, the report's text or the tracker's thread
// count, which change no result.
// An identity check against mixing results of different studies, not a security measure.
std::string study_hash(const Study& study);

struct StudyUnit {
  int index = 0;     // position in the study's canonical order
  std::string part;  // "table", "sweep", "pareto" or "loso"
  // table: method * sequences + sequence; sweep: index into sweep_units; pareto: into pairs;
  // loso: into loso_units
  int item = 0;
  std::string id;  // stable and unique, e.g. "table/1-weighted/0-freiburg1_rpy", "sweep/0-fr1/lambda-2=1000"
};

// Table units (row-major), then sweep units, then Pareto pairs, then LOSO runs.
std::vector<StudyUnit> study_units(const Study& study);

// The tracker options of the parts (with the study's tracker in them).
MatrixOptions table_options(const Study& study);
SweepOptions sweep_options(const Study& study);
ParetoStudyOptions pareto_options(const Study& study, int pair_index);
LosoOptions loso_options(const Study& study);

// "I/N" with 0 <= I < N; throws bivo::Error naming the text otherwise.
struct ShardSpec {
  int index = 0, count = 1;
};
ShardSpec parse_shard(const std::string& text);

// The units of shard I of N: the units are permuted by the study's seed (SplitMix64 +
// Fisher-Yates, the same on every machine) and dealt in turn, so shards are disjoint,
// cover every unit, and mix cheap and expensive kinds of unit.
std::vector<StudyUnit> shard_units(const Study& study, const ShardSpec& shard);

}  // namespace bivo::experiments
