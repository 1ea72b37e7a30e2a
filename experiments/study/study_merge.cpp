// Unit results -> the command's outputs (study_merge.h).
#include "experiments/study/study_merge.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include <nlohmann/json.hpp>

#include "experiments/study/study_plan.h"
#include "experiments/study/study_results.h"
#include "experiments/tracker_config.h"
#include "odometry/io/atomic_file.h"
#include "solvers/error.h"

namespace bivo::experiments {
namespace {

using json = nlohmann::json;
namespace fs = std::filesystem;

// The result of a unit, decoded; a decoding error names the unit (and so its file).
template <class F>
auto decode(const StudyUnit& unit, const json& j, F f) {
  try {
    return f(j);
  } catch (const json::exception& e) {
    throw Error("result of unit '" + unit.id + "' is malformed: " + e.what());
  } catch (const Error& e) {
    throw Error("result of unit '" + unit.id + "' is malformed: " + e.what());
  }
}

MethodMatrix merged_matrix(const Study& study, const std::vector<StudyUnit>& units,
                           const std::map<std::string, json>& results) {
  const MatrixOptions o = table_options(study);
  std::vector<MatrixCell> cells;
  for (const StudyUnit& u : units) {
    if (u.part != "table") continue;
    const auto it = results.find(u.id);
    if (it != results.end()) {
      cells.push_back(decode(u, it->second, matrix_cell_from_json));
      continue;
    }
    MatrixCell c;  // partial merge: the cell stays empty, and says why
    const int n = int(o.sequences.size());
    c.sequence_dir = o.sequences[u.item % n];
    c.sequence = sequence_labels(o.sequences).at(u.item % n);
    c.spec = o.methods[u.item / n];
    odometry::TrackerOptions t = o.tracker;
    t.method = c.spec.method;
    t.backend = c.spec.backend;
    c.backend = effective_backend(t);
    c.note = "not run (unit " + u.id + " missing from the results)";
    cells.push_back(c);
  }
  return assemble_matrix(o, std::move(cells));
}

SweepResult merged_sweep(const Study& study, const std::vector<StudyUnit>& units,
                         const std::map<std::string, json>& results) {
  const SweepOptions o = sweep_options(study);
  const std::vector<SweepUnit> su = sweep_units(o);
  std::vector<SweepRun> runs;
  for (const StudyUnit& u : units) {
    if (u.part != "sweep") continue;
    const auto it = results.find(u.id);
    if (it != results.end()) {
      runs.push_back(decode(u, it->second, sweep_run_from_json));
      continue;
    }
    SweepRun r;
    r.unit = su.at(u.item);
    r.sequence = sequence_labels(o.sequences).at(r.unit.sequence);
    r.missing = true;
    runs.push_back(r);
  }
  return assemble_sweep(o, runs);
}

struct MergedPareto {
  ParetoOutcome outcome;
  bool missing = false;
};
std::vector<MergedPareto> merged_pareto(const std::vector<StudyUnit>& units,
                                        const std::map<std::string, json>& results) {
  std::vector<MergedPareto> out;
  for (const StudyUnit& u : units) {
    if (u.part != "pareto") continue;
    const auto it = results.find(u.id);
    if (it != results.end()) {
      out.push_back({decode(u, it->second, pareto_outcome_from_json), false});
    } else {
      out.push_back({{std::nullopt, "not run (unit " + u.id + " missing from the results)"}, true});
    }
  }
  return out;
}

// The LOSO runs in unit order; a missing one (partial merge) is a failed run that says why.
LosoResult merged_loso(const Study& study, const std::vector<StudyUnit>& units,
                       const std::map<std::string, json>& results) {
  const LosoOptions o = loso_options(study);
  const std::vector<LosoRun> planned = loso_units(o);
  std::vector<LosoRun> runs;
  for (const StudyUnit& u : units) {
    if (u.part != "loso") continue;
    const auto it = results.find(u.id);
    if (it != results.end()) {
      runs.push_back(decode(u, it->second, loso_run_from_json));
      continue;
    }
    LosoRun r = planned.at(u.item);
    r.sequence_name = fs::path(o.sequences.at(r.sequence)).filename().string();
    r.error = "not run (unit " + u.id + " missing from the results)";
    runs.push_back(r);
  }
  return assemble_loso(o, std::move(runs));
}

}  // namespace

CollectedResults collect_results(const Study& study, const std::string& dir) {
  if (!fs::is_directory(dir)) throw Error("results folder '" + dir + "' does not exist");
  const std::string hash = study_hash(study);
  const std::vector<StudyUnit> units = study_units(study);
  std::set<std::string> ids;
  for (const auto& u : units) ids.insert(u.id);
  std::vector<std::string> paths;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (e.path().extension() != ".json") continue;
    // A result file's name on something else (a folder) would leave its unit silently missing.
    if (!e.is_regular_file()) throw Error("result file '" + e.path().string() + "' is not a regular file");
    paths.push_back(e.path().string());
  }
  std::sort(paths.begin(), paths.end());
  CollectedResults out;
  for (const std::string& path : paths) {
    UnitResultFile f = read_unit_result(path);
    check_unit_result(f, hash);
    if (!ids.count(f.unit))
      throw Error("result file '" + path + "' holds unit '" + f.unit + "', which the study does not have");
    ++out.files;
    out.versions.insert(f.bivo_version);
    auto& dups = out.duplicated[f.unit];
    dups.push_back(path);
    if (dups.size() == 1) out.by_unit.emplace(f.unit, std::move(f));
  }
  for (auto it = out.duplicated.begin(); it != out.duplicated.end();) {
    it = it->second.size() > 1 ? std::next(it) : out.duplicated.erase(it);
  }
  for (const auto& u : units) {
    if (!out.by_unit.count(u.id)) out.missing.push_back(u.id);
  }
  return out;
}

bool complete(const CollectedResults& r) { return r.missing.empty() && r.duplicated.empty(); }

std::string completeness_text(const CollectedResults& r) {
  std::ostringstream s;
  if (complete(r)) {
    s << "complete: " << r.by_unit.size() << " unit(s), one result file each\n";
  }
  if (!r.missing.empty()) {
    s << r.missing.size() << " unit(s) missing:\n";
    for (const auto& id : r.missing) s << "  " << id << "\n";
  }
  if (!r.duplicated.empty()) {
    s << r.duplicated.size() << " unit(s) with more than one result file:\n";
    for (const auto& [id, paths] : r.duplicated) {
      s << "  " << id << ":";
      for (const auto& p : paths) s << " " << p;
      s << "\n";
    }
  }
  if (r.versions.size() > 1) {
    s << "warning: results written by different bivo versions:";
    for (const auto& v : r.versions) s << " " << v;
    s << "\n";
  }
  return s.str();
}

MergeOutput merge_results(const Study& study, const std::map<std::string, json>& results, const std::string& dir) {
  check_study(study);
  const std::vector<StudyUnit> units = study_units(study);
  odometry::io::create_output_directory(dir);
  MergeOutput out;
  out.units = int(units.size());
  for (const StudyUnit& u : units) {
    const auto it = results.find(u.id);
    if (it == results.end()) continue;
    std::string why;
    try {
      why = unit_failure(u, it->second);
    } catch (const json::exception& e) {
      throw Error("result of unit '" + u.id + "' is malformed: " + e.what());
    }
    if (!why.empty()) out.failures.push_back(u.id + ": " + why);
  }
  if (study.kind == "table") {
    const MethodMatrix m = merged_matrix(study, units, results);
    write_matrix_trajectories(m, dir + "/trajectories");
    out.markdown = write_matrix(m, dir);
  } else if (study.kind == "sweep") {
    out.markdown = write_sweep(merged_sweep(study, units, results), dir);
  } else if (study.kind == "pareto") {
    std::vector<ParetoStudy> studies;
    for (const MergedPareto& p : merged_pareto(units, results)) {
      // A pair whose study failed (counted in out.failures) or that is missing (partial
      // merge) is left out; the others are written.
      if (p.outcome.study) studies.push_back(*p.outcome.study);
    }
    out.markdown = write_pareto_studies(studies, study.pareto->options.methods, dir, study.plots);
  } else if (study.kind == "loso") {
    out.markdown = write_loso(merged_loso(study, units, results), dir);
  } else {
    ReportParts parts;
    parts.matrix = merged_matrix(study, units, results);
    if (study.sweep && !study.sweep->sequences.empty()) parts.sweep = merged_sweep(study, units, results);
    if (study.pareto) {
      const std::vector<MergedPareto> outcomes = merged_pareto(units, results);
      for (size_t k = 0; k < outcomes.size(); ++k) {
        parts.pareto.push_back({sequence_label(study.pareto->pairs[k].sequence_dir), outcomes[k].outcome.study,
                                outcomes[k].outcome.error});
      }
    }
    out.report = write_report(report_options(study), parts, dir);
    out.markdown = out.report->tables_markdown;
  }
  if (study.kind != "report") write_tracker_config(dir + "/config.json", study.tracker);
  write_study(dir + "/study.json", study);
  return out;
}

MergeOutput run_study(const Study& study, std::ostream* log) {
  check_study(study);
  const std::vector<StudyUnit> units = study_units(study);
  std::map<std::string, json> results;
  for (const StudyUnit& u : units) {
    const auto t0 = std::chrono::steady_clock::now();
    results[u.id] = run_unit(study, u);
    if (log) {
      *log << "[" << u.index + 1 << "/" << units.size() << "] " << u.id << " " << std::fixed << std::setprecision(1)
           << std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() << " s\n"
           << std::defaultfloat << std::flush;
    }
  }
  return merge_results(study, results, study.output);
}

}  // namespace bivo::experiments
