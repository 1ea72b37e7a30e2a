#pragma once
// Running a study's work units (`bivo work STUDY --shard I/N`): one result file per unit,
// written atomically (temporary + rename), so a killed shard loses only the unit it was
// running, and a re-run skips every unit whose result file is already there (resume).
//
// A result file:
//   {"format": "bivo-unit-result", "version": 1, "study_hash": "<study_hash>",
//    "unit": "<unit id>", "bivo_version": "0.1", "host": "node17",
//    "finished": "2024-05-01T12:00:00Z", "seconds": 12.3, "result": {...study_results.h...}}
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "experiments/study/study.h"

namespace bivo::experiments {

// The version of bivo (CMake's project version).
std::string bivo_version();
// The host name of this machine.
std::string host_name();

// Where results go when no folder is given: "runs/s.json" -> "runs/s.results".
std::string default_results_dir(const std::string& study_path);

// "u00007_table_1-weighted_0-seq.json": the unit's index and id, file-name safe.
std::string unit_file_name(const StudyUnit& unit);

// Runs one unit in this process and returns its result (study_results.h). Failures of the
// run itself (bivo::Error) are part of the result, as the single-process commands record them.
nlohmann::json run_unit(const Study& study, const StudyUnit& unit);

// Why a unit produced no result, "" when it did: a table cell whose run failed, a sweep point
// whose run failed, a Pareto pair whose study threw, a LOSO run that failed. Commands exit
// non-zero on any.
std::string unit_failure(const StudyUnit& unit, const nlohmann::json& result);

struct UnitResultFile {
  std::string path, study_hash, unit, bivo_version, host, finished;
  double seconds = 0;
  nlohmann::json result;
};

// Reads one result file. Throws bivo::Error naming the path when it is truncated or not a
// unit result (does not parse, a field is missing).
UnitResultFile read_unit_result(const std::string& path);
// Throws bivo::Error naming the path when the file belongs to another study.
void check_unit_result(const UnitResultFile& file, const std::string& study_hash);

void write_unit_result(const std::string& path, const std::string& study_hash, const StudyUnit& unit,
                       const nlohmann::json& result, double seconds);

struct WorkSummary {
  int units = 0;                    // in the shard
  int ran = 0;                      // run now
  int skipped = 0;                  // finished earlier (resume)
  std::vector<std::string> failed;  // "unit id: why" of the units run now that produced no result
};

// Runs the units of `shard` that have no valid result file in results_dir (created), one
// after the other, logging one line per unit to `log`. A result file of another study in
// the way is an error (nothing is overwritten); an unreadable one (truncated by a full disk,
// say) is redone.
WorkSummary work_shard(const Study& study, const ShardSpec& shard, const std::string& results_dir, std::ostream& log);

}  // namespace bivo::experiments
