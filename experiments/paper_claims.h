#pragma once
// The paper's claims, one row each, checked against a run's results: tables 1-2 (RPE of each
// method vs single per Structure-vs-Texture category, the best method per category, the
// texture drop of single), table 3 (runtimes), fig. 3 (error vs lambda) and fig. 5
// (per-frame translational error on poor texture). The paper's numbers are constants cited
// by table; bivo's numbers are computed from the MethodMatrix (and the sweep, when run) and
// never stored. A category is read from the sequence name ("[no]structure_[no]texture_
// near|far", real or synthetic); rows whose inputs are missing are left out.
#include <optional>
#include <string>
#include <vector>

#include "experiments/method_matrix.h"
#include "experiments/parameter_sweep.h"

namespace bivo::experiments {

struct ClaimRow {
  std::string source;    // "table 1", "fig. 3a", ...
  std::string claim;     // what the paper says
  std::string category;  // Structure-vs-Texture category, or "all"
  std::string paper;     // the paper's number(s)
  std::string bivo;      // the run's number(s)
  bool holds = false;
  std::string criterion;  // how "holds" was decided
};

std::vector<ClaimRow> paper_claims(const MethodMatrix& matrix, const SweepResult* sweep = nullptr);
// "| source | claim | category | paper | bivo | here |" table; a note when there is no row.
std::string claims_markdown(const std::vector<ClaimRow>& rows);
// "structure_notexture_near" from a folder name, or "" when the name names no category.
std::string category_of(const std::string& sequence_name);

}  // namespace bivo::experiments
