#include "experiments/profile_study.h"

#include <algorithm>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include <nlohmann/json.hpp>

#include "experiments/result_table.h"
#include "experiments/sequence_runner.h"
#include "odometry/io/atomic_file.h"
#include "odometry/kernels/kernels.h"
#include "solvers/error.h"

namespace bivo::experiments {
namespace {

const std::vector<std::string> kPhases = {"pyramid", "reference", "residuals", "weights", "normal_equations",
                                          "cone_data", "subproblem", "other"};

// The paper's table 3 (runtime per match) for our methods, with the factor over the
// Gauss-Newton reference (the first row) and, for the SOCP rows, the interior-point share.
std::string runtime_table(const std::vector<ProfileRow>& rows) {
  std::ostringstream md;
  if (rows.empty() || rows.front().pairs == 0) return "";
  const double ref = rows.front().total_ms;
  md << "\nRuntime per frame pair, as the paper's table 3 (single objective 15.42 ms, Tykkala 21.06, weighted "
        "sum 22.99, bounded objective with an SOCP solver 7093 ms):\n\n| method | backend | pairs | runtime [ms] | "
        "x single:gn | of which IPM [ms] |\n|---|---|---:|---:|---:|---:|\n";
  for (const auto& r : rows) {
    if (r.pairs == 0) continue;
    double ipm = 0;
    for (const auto& [name, ms] : r.phase_ms) {
      if (name.rfind("subproblem/ipm_", 0) == 0) ipm += ms;
    }
    md << "| " << r.method << " | " << r.backend << " | " << r.pairs << " | " << std::fixed << std::setprecision(2)
       << r.total_ms << " | " << std::setprecision(1) << (ref > 0 ? r.total_ms / ref : 0.0) << " | ";
    if (ipm > 0) md << std::setprecision(2) << ipm;
    md << " |\n" << std::defaultfloat;
  }
  return md.str();
}

}  // namespace

std::vector<ProfileRow> run_profile(const ProfileOptions& o) {
  std::vector<MethodSpec> methods = o.methods;
  const bool has_reference = !methods.empty() && methods.front().method == "single" &&
                             (methods.front().backend.empty() || methods.front().backend == "gn");
  if (!has_reference) methods.insert(methods.begin(), MethodSpec{"single", "gn"});
  for (const auto& m : methods) {
    odometry::TrackerOptions t = o.tracker;
    t.method = m.method;
    t.backend = m.backend;
    odometry::validate(t);
  }
  std::vector<ProfileRow> rows;
  std::vector<odometry::PairResult> reference;
  for (const auto& m : methods) {
    RunRequest req;
    req.sequence_dir = o.sequence_dir;
    req.tracker = o.tracker;
    req.tracker.method = m.method;
    req.tracker.backend = m.backend;
    req.tracker.evaluate_unused_objective = true;  // single's F_D is the reference of the F_D ratio
    req.first_frame = o.first_frame;
    req.max_frames = o.max_frames;
    if (m.backend.rfind("ipm-", 0) == 0 && o.socp_max_frames > 0) {
      req.max_frames = o.max_frames > 0 ? std::min(o.max_frames, o.socp_max_frames) : o.socp_max_frames;
    }
    req.progress = o.progress;
    ProfileRow row;
    row.method = m.method;
    row.backend = effective_backend(req.tracker);
    RunOutcome run;
    try {
      run = run_sequence(req);
    } catch (const Error& e) {
      row.note = e.what();
      rows.push_back(row);
      continue;
    }
    row.pairs = int(run.pairs.size());
    const double n = row.pairs;
    double total = 0;
    for (const auto& p : run.pairs) total += p.seconds;
    row.total_ms = 1000.0 * total / n;
    for (const auto& phase : kPhases) {
      double s = 0;
      for (const auto& p : run.pairs) s += p.profile.seconds(phase);
      row.phase_ms[phase] = 1000.0 * s / n;
    }
    // Phases recorded under other names (a backend's own) are kept too.
    for (const auto& p : run.pairs) {
      for (const auto& [name, sec] : p.profile.all()) {
        if (!row.phase_ms.count(name) || std::find(kPhases.begin(), kPhases.end(), name) == kPhases.end()) {
          row.phase_ms[name] += 1000.0 * sec / n;
        }
      }
    }
    row.iterations_per_level.assign(o.tracker.levels, 0.0);
    std::vector<double> gap(o.tracker.levels, 0.0), ratio(o.tracker.levels, 0.0);
    std::vector<int> gap_n(o.tracker.levels, 0);
    for (size_t k = 0; k < run.pairs.size(); ++k) {
      for (const auto& lr : run.pairs[k].levels) {
        if (lr.level < 0 || lr.level >= o.tracker.levels) continue;
        row.iterations_per_level[lr.level] += lr.iterations / n;
        if (rows.empty() || k >= reference.size() || lr.skipped) continue;
        for (const auto& ref : reference[k].levels) {
          if (ref.level == lr.level && !ref.skipped && ref.f_i > 0 && ref.f_d > 0) {
            gap[lr.level] += (lr.f_i - ref.f_i) / ref.f_i;
            ratio[lr.level] += lr.f_d / ref.f_d;
            ++gap_n[lr.level];
          }
        }
      }
    }
    if (!rows.empty()) {
      for (int l = 0; l < o.tracker.levels; ++l) {
        row.f_i_gap.push_back(gap_n[l] ? gap[l] / gap_n[l] : 0.0);
        row.f_d_ratio.push_back(gap_n[l] ? ratio[l] / gap_n[l] : 0.0);
      }
    } else {
      reference = run.pairs;
    }
    rows.push_back(row);
  }
  return rows;
}

std::string write_profile(const std::vector<ProfileRow>& rows, const std::string& dir) {
  std::filesystem::create_directories(dir);
  std::vector<std::string> phases = kPhases;
  for (const auto& r : rows) {
    for (const auto& [name, ms] : r.phase_ms) {
      if (std::find(phases.begin(), phases.end(), name) == phases.end()) phases.push_back(name);
    }
  }
  std::ostringstream md, csv;
  // Per-phase times depend on the kernels' instruction set: name it beside them.
  const std::string kernels = odometry::to_string(odometry::default_kernels().isa);
  md << "Per-pixel kernels: " << kernels << " (the best instruction set of this CPU; avx2 and avx512vl give "
        "bit-identical results, avx512's sixteen lanes agree with them to float rounding)\n\n";
  md << "Time per frame pair by phase [ms] (mean over pairs; 'a/b' is a part of phase 'a'; 'unrecorded' = total "
        "minus the phases; with --threads 2 or more the next frame's pyramid is built beside the other phases, "
        "so 'unrecorded' can be negative):\n\n"
        "| method | backend | pairs | total |";
  csv << "method,backend,pairs,total_ms";
  for (const auto& p : phases) {
    md << " " << p << " |";
    csv << "," << p << "_ms";
  }
  md << " unrecorded |\n|---|---|---:|---:|";
  csv << ",unrecorded_ms";
  for (size_t i = 0; i <= phases.size(); ++i) md << "---:|";
  md << "\n";
  const int levels = rows.empty() ? 0 : int(rows.front().iterations_per_level.size());
  for (int l = 0; l < levels; ++l) csv << ",iterations_level" << l;
  for (int l = 0; l < levels; ++l) csv << ",f_i_gap_level" << l << ",f_d_ratio_level" << l;
  csv << "\n";
  nlohmann::json j = nlohmann::json::array();
  for (const auto& r : rows) {
    double recorded = 0;
    md << "| " << r.method << " | " << r.backend << " | " << r.pairs << " | " << std::fixed << std::setprecision(2)
       << r.total_ms << " |";
    csv << r.method << "," << r.backend << "," << r.pairs << "," << std::setprecision(6) << r.total_ms;
    for (const auto& p : phases) {
      const auto it = r.phase_ms.find(p);
      const double v = it == r.phase_ms.end() ? 0.0 : it->second;
      if (p.find('/') == std::string::npos) recorded += v;  // "a/b" is a part of "a"
      md << " " << std::setprecision(2) << v << " |";
      csv << "," << std::setprecision(6) << v;
    }
    md << " " << std::setprecision(2) << r.total_ms - recorded << " |\n";
    csv << "," << std::setprecision(6) << r.total_ms - recorded;
    for (double it : r.iterations_per_level) csv << "," << it;
    for (int l = 0; l < levels; ++l) {
      if (r.f_i_gap.empty()) csv << ",,";
      else csv << "," << r.f_i_gap[l] << "," << r.f_d_ratio[l];
    }
    csv << "\n" << std::defaultfloat;
    md << std::defaultfloat;
    j.push_back({{"method", r.method}, {"backend", r.backend}, {"pairs", r.pairs}, {"total_ms", r.total_ms},
                 {"phase_ms", r.phase_ms}, {"iterations_per_level", r.iterations_per_level},
                 {"f_i_gap_per_level", r.f_i_gap}, {"f_d_ratio_per_level", r.f_d_ratio}, {"note", r.note},
                 {"kernels", kernels}});
  }
  md << "\nOuter iterations per pyramid level (mean over pairs; level 0 = full resolution), and per level the "
        "gap to the single-objective Gauss-Newton solution: (F_I - F_I,gn)/F_I,gn and F_D/F_D,gn:\n\n| method | "
        "backend |";
  for (int l = levels - 1; l >= 0; --l) md << " it L" << l << " |";
  for (int l = levels - 1; l >= 0; --l) md << " F_I gap L" << l << " | F_D ratio L" << l << " |";
  md << "\n|---|---|";
  for (int i = 0; i < 3 * levels; ++i) md << "---:|";
  md << "\n";
  for (const auto& r : rows) {
    md << "| " << r.method << " | " << r.backend << " |";
    for (int l = levels - 1; l >= 0; --l) md << " " << std::fixed << std::setprecision(1) << r.iterations_per_level[l] << " |";
    for (int l = levels - 1; l >= 0; --l) {
      if (r.f_i_gap.empty()) md << " (reference) | (reference) |";
      else md << " " << std::showpos << std::setprecision(4) << r.f_i_gap[l] << std::noshowpos << " | " << r.f_d_ratio[l] << " |";
    }
    md << std::defaultfloat << "\n";
  }
  md << runtime_table(rows);
  for (const auto& r : rows) {
    if (!r.note.empty()) md << "\n- " << r.method << " (" << r.backend << "): " << r.note;
  }
  md << "\n";
  odometry::io::write_file_atomically(dir + "/profile.md", [&](std::ostream& o) { o << md.str(); });
  odometry::io::write_file_atomically(dir + "/profile.csv", [&](std::ostream& o) { o << csv.str(); });
  odometry::io::write_file_atomically(dir + "/profile.json", [&](std::ostream& o) { o << j.dump(2) << "\n"; });
  return md.str();
}

}  // namespace bivo::experiments
