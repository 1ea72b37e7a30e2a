#pragma once
// What a study's work unit produced, as JSON (the "result" of a unit's result file,
// study_work.h): the engines' own result types, written so that reading gives back the
// same doubles bit for bit (non-finite values as the strings "inf", "-inf", "nan"; poses as
// their 3x4 matrices), so tables assembled from result files equal those of one process.
//
// A table cell keeps its run's ground truth only within 1 s of the processed window: all
// that RPE, ATE and the per-pair errors of the window read.
#include <optional>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "experiments/loso.h"
#include "experiments/method_matrix.h"
#include "experiments/parameter_sweep.h"
#include "experiments/pareto_study.h"

namespace bivo::experiments {

nlohmann::json matrix_cell_to_json(const MatrixCell& cell);
MatrixCell matrix_cell_from_json(const nlohmann::json& j);

nlohmann::json sweep_run_to_json(const SweepRun& run);
SweepRun sweep_run_from_json(const nlohmann::json& j);

// A Pareto unit: its study, or the error that stopped it.
struct ParetoOutcome {
  std::optional<ParetoStudy> study;
  std::string error;
};
nlohmann::json pareto_outcome_to_json(const ParetoOutcome& outcome);
ParetoOutcome pareto_outcome_from_json(const nlohmann::json& j);

nlohmann::json loso_run_to_json(const LosoRun& run);
LosoRun loso_run_from_json(const nlohmann::json& j);

// The readers throw nlohmann::json::exception on a missing key or a wrong type; callers
// name the file (study_merge.h).

}  // namespace bivo::experiments
