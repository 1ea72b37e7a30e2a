// Work units, their result files and resume (study_work.h).
#include "experiments/study/study_work.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <optional>
#include <sstream>

#include "experiments/study/study_results.h"
#include "experiments/trajectory_evaluation.h"
#include "odometry/io/atomic_file.h"
#include "odometry/io/json_file.h"
#include "solvers/error.h"

#ifndef BIVO_VERSION
#define BIVO_VERSION "unknown"
#endif

namespace bivo::experiments {
namespace {

using json = nlohmann::json;
namespace fs = std::filesystem;

std::string now_utc() {
  const std::time_t t = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return buf;
}

}  // namespace

std::string bivo_version() { return BIVO_VERSION; }

std::string host_name() {
  char buf[256] = {0};
  if (::gethostname(buf, sizeof buf - 1) != 0) return "unknown";
  return buf;
}

std::string default_results_dir(const std::string& study_path) {
  fs::path p(study_path);
  if (p.extension() == ".json") p.replace_extension();
  return p.string() + ".results";
}

std::string unit_file_name(const StudyUnit& unit) {
  char index[16];
  std::snprintf(index, sizeof index, "u%05d_", unit.index);
  std::string id = unit.id;
  for (char& c : id) {
    if (c == '/') c = '_';
  }
  return index + id + ".json";
}

json run_unit(const Study& study, const StudyUnit& unit) {
  if (unit.part == "table") {
    const MatrixOptions o = table_options(study);
    const int n = int(o.sequences.size());
    return matrix_cell_to_json(run_matrix_cell(o, unit.item / n, unit.item % n));
  }
  if (unit.part == "sweep") {
    const SweepOptions o = sweep_options(study);
    return sweep_run_to_json(run_sweep_unit(o, sweep_units(o).at(unit.item)));
  }
  if (unit.part == "pareto") {
    ParetoOutcome out;
    try {
      out.study = run_pareto_study(pareto_options(study, unit.item));
    } catch (const Error& e) {
      out.error = e.what();
    }
    return pareto_outcome_to_json(out);
  }
  if (unit.part == "loso") {
    const LosoOptions o = loso_options(study);
    LosoRun run = loso_units(o).at(unit.item);
    run_loso_unit(o, run);
    return loso_run_to_json(run);
  }
  throw Error("study: unit '" + unit.id + "' of unknown part '" + unit.part + "'");
}

std::string unit_failure(const StudyUnit& unit, const json& result) {
  if (unit.part == "table") return result.at("run").is_null() ? result.at("note").get<std::string>() : "";
  if (unit.part == "sweep") {  // a run too short for its RPE windows is a result ("too short"), not a failure
    const std::string error = result.at("ok").get<bool>() ? "" : result.at("error").get<std::string>();
    return is_too_short(error) ? "" : error;
  }
  if (unit.part == "pareto") return result.at("error").get<std::string>();
  if (unit.part == "loso") return result.at("ok").get<bool>() ? "" : result.at("error").get<std::string>();
  return "";
}

UnitResultFile read_unit_result(const std::string& path) {
  json j;
  try {
    j = odometry::io::read_json_file(path, "result file");
  } catch (const Error& e) {
    throw Error("result file '" + path + "' is truncated or corrupt (" + e.what() + ")");
  }
  UnitResultFile f;
  f.path = path;
  try {
    if (j.at("format").get<std::string>() != "bivo-unit-result") throw Error("not a bivo unit result");
    if (j.at("version").get<int>() != 1) throw Error("result format version " + j.at("version").dump());
    f.study_hash = j.at("study_hash").get<std::string>();
    f.unit = j.at("unit").get<std::string>();
    f.bivo_version = j.at("bivo_version").get<std::string>();
    f.host = j.at("host").get<std::string>();
    f.finished = j.at("finished").get<std::string>();
    f.seconds = j.at("seconds").get<double>();
    f.result = j.at("result");
  } catch (const json::exception& e) {
    throw Error("result file '" + path + "' is truncated or corrupt (" + e.what() + ")");
  } catch (const Error& e) {
    throw Error("result file '" + path + "' is not a unit result: " + e.what());
  }
  return f;
}

void check_unit_result(const UnitResultFile& file, const std::string& study_hash) {
  if (file.study_hash != study_hash) {
    throw Error("result file '" + file.path + "' belongs to another study (hash " + file.study_hash +
                ", this study's is " + study_hash + ")");
  }
}

void write_unit_result(const std::string& path, const std::string& study_hash, const StudyUnit& unit,
                       const json& result, double seconds) {
  const json j = {{"format", "bivo-unit-result"},
                  {"version", 1},
                  {"study_hash", study_hash},
                  {"unit", unit.id},
                  {"bivo_version", bivo_version()},
                  {"host", host_name()},
                  {"finished", now_utc()},
                  {"seconds", seconds},
                  {"result", result}};
  const std::string text = j.dump() + "\n";
  odometry::io::write_file_atomically(path, [&](std::ostream& out) { out << text; });
}

WorkSummary work_shard(const Study& planned, const ShardSpec& shard, const std::string& dir, std::ostream& log) {
  const std::string hash = study_hash(planned);
  const std::vector<StudyUnit> units = shard_units(planned, shard);
  // A shard is one of as many jobs as there are cores (GNU Parallel's --jobs default, a
  // Slurm task's --cpus-per-task): a frame loader thread beside its tracker would take
  // another shard's core and stretch every pair's wall time. Frames load between pairs.
  Study study = planned;
  study.tracker.prefetch_frames = false;
  odometry::io::create_output_directory(dir);
  WorkSummary summary;
  summary.units = int(units.size());
  int k = 0;
  for (const StudyUnit& unit : units) {
    ++k;
    const std::string path = (fs::path(dir) / unit_file_name(unit)).string();
    if (fs::exists(path)) {
      std::optional<UnitResultFile> done;
      try {
        done = read_unit_result(path);
      } catch (const Error& e) {
        log << "work: redoing " << unit.id << ": " << e.what() << "\n";
      }
      if (done) {
        check_unit_result(*done, hash);  // never overwrite another study's results
        if (done->unit != unit.id) {
          throw Error("result file '" + path + "' holds unit '" + done->unit + "', expected '" + unit.id + "'");
        }
        ++summary.skipped;
        continue;
      }
    }
    // The temporaries of a run killed while writing this file go when it is written again
    // (odometry/io/own_temporaries.h).
    const auto t0 = std::chrono::steady_clock::now();
    const json result = run_unit(study, unit);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    write_unit_result(path, hash, unit, result, seconds);
    ++summary.ran;
    if (const std::string why = unit_failure(unit, result); !why.empty())
      summary.failed.push_back(unit.id + ": " + why);
    log << "work: [" << k << "/" << units.size() << "] " << unit.id << " " << std::fixed << std::setprecision(1)
        << seconds << " s" << std::defaultfloat << std::endl;
  }
  log << "work: shard " << shard.index << "/" << shard.count << ": " << summary.ran << " unit(s) run, "
      << summary.skipped << " already done, " << summary.units << " in the shard\n";
  return summary;
}

}  // namespace bivo::experiments
