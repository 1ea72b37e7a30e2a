#pragma once
// From unit results to the outputs of the single-process command (`bivo merge`, and the
// last step of `bivo table/sweep/pareto/report/loso` themselves): the same tables, JSON/CSV
// and plots, written by the same engine functions (write_matrix, write_sweep,
// write_pareto_studies, write_report, write_loso), so merging shards gives the bytes of one
// process (timing columns aside).
#include <map>
#include <optional>
#include <ostream>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "experiments/report_builder.h"
#include "experiments/study/study.h"
#include "experiments/study/study_work.h"

namespace bivo::experiments {

struct CollectedResults {
  std::map<std::string, UnitResultFile> by_unit;               // unit id -> its file (first by path)
  std::vector<std::string> missing;                            // unit ids, in study order
  std::map<std::string, std::vector<std::string>> duplicated;  // unit id -> every path holding it
  std::set<std::string> versions;                              // bivo versions that wrote them
  int files = 0;
};

// Every *.json file under results_dir (recursively: copies from several hosts may sit in
// sub-folders; temporaries of killed runs are not *.json). Throws bivo::Error naming the
// file for a truncated or corrupt result, a result of another study (hash) and a unit the
// study does not have.
CollectedResults collect_results(const Study& study, const std::string& results_dir);

// "complete: 14 units" or the missing and duplicated units, one per line.
std::string completeness_text(const CollectedResults& results);
bool complete(const CollectedResults& results);

struct MergeOutput {
  std::string markdown;                // what the single-process command prints
  std::optional<ReportResult> report;  // kind "report"
  int units = 0;                       // the study's
  std::vector<std::string> failures;   // "unit id: why" of the results that are failures (unit_failure)
};

// Assembles the results (unit id -> result; a missing unit becomes a missing cell / a note)
// and writes the command's outputs, config.json and study.json into output_dir.
MergeOutput merge_results(const Study& study, const std::map<std::string, nlohmann::json>& results,
                          const std::string& output_dir);

// The single-process commands: every unit in this process (progress on `log`), then
// merge_results into study.output.
MergeOutput run_study(const Study& study, std::ostream* log = nullptr);

}  // namespace bivo::experiments
