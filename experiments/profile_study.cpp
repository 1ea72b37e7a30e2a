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

const std::vector<std::string> kPhases = {"pyramid",          "reference", "residuals",  "weights",
                                          "normal_equations", "cone_data", "subproblem", "other"};

// The paper's table 3 (runtime per match) for our methods, with the factor over the
// Gauss-Newton reference (the first row) and, for the SOCP rows, the interior-point share.
std::string runtime_table(const std::vector<ProfileRow>& rows) {
  std::ostringstream md;
  if (rows.empty() || rows.front().pairs == 0) return "";
  const double ref = rows.front().median_ms;
  md << "\nRuntime per frame pair, as the paper's table 3 (single objective 15.42 ms, Tykkala 21.06, weighted "
        "sum 22.99, bounded objective with an SOCP solver 7093 ms); median and quartiles over every pair of every "
        "repetition, the factor on medians:\n\n| method | backend | pairs x reps | mean [ms] | median [ms] | "
        "quartiles [ms] | x single:gn | of which IPM [ms] |\n|---|---|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& r : rows) {
    if (r.pairs == 0) continue;
    double ipm = 0;
    for (const auto& [name, ms] : r.phase_ms) {
      if (name.rfind("subproblem/ipm_", 0) == 0) ipm += ms;
    }
    md << "| " << r.method << " | " << r.backend << " | " << r.pairs << " x " << r.repetitions << " | " << std::fixed
       << std::setprecision(2) << r.total_ms << " | " << r.median_ms << " | " << r.q1_ms << "-" << r.q3_ms << " | "
       << std::setprecision(3) << (ref > 0 ? r.median_ms / ref : 0.0) << " | ";
    if (ipm > 0) md << std::setprecision(2) << ipm;
    md << " |\n" << std::defaultfloat;
  }
  return md.str();
}

}  // namespace

namespace {

// The value below which a fraction q of the sorted values lie (linear interpolation).
double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const double at = q * double(v.size() - 1);
  const std::size_t lo = std::size_t(at);
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (at - double(lo)) * (v[hi] - v[lo]);
}

// One method's row from its runs (one per repetition; every run holds the same pairs and
// results, only their times differ) and the reference's pairs (empty for the reference).
ProfileRow row_of(ProfileRow row, const std::vector<RunOutcome>& runs,
                  const std::vector<odometry::PairResult>& reference, bool is_reference, int levels) {
  if (runs.empty()) return row;
  std::vector<double> pair_ms;
  for (const auto& run : runs) {
    for (const auto& p : run.pairs) pair_ms.push_back(1000.0 * p.seconds);
  }
  row.pairs = int(runs.front().pairs.size());
  row.repetitions = int(runs.size());
  const double n = double(pair_ms.size());
  double total = 0;
  for (double ms : pair_ms) total += ms;
  row.total_ms = total / n;
  row.median_ms = quantile(pair_ms, 0.5);
  row.q1_ms = quantile(pair_ms, 0.25);
  row.q3_ms = quantile(pair_ms, 0.75);
  for (const auto& phase : kPhases) row.phase_ms[phase] = 0.0;
  // Phases recorded under other names (a backend's own) are kept too.
  for (const auto& run : runs) {
    for (const auto& p : run.pairs) {
      for (const auto& [name, sec] : p.profile.all()) row.phase_ms[name] += 1000.0 * sec / n;
    }
  }
  const std::vector<odometry::PairResult>& pairs = runs.front().pairs;
  const double np = double(pairs.size());
  row.iterations_per_level.assign(levels, 0.0);
  std::vector<double> gap(levels, 0.0), ratio(levels, 0.0);
  std::vector<int> gap_n(levels, 0);
  for (size_t k = 0; k < pairs.size(); ++k) {
    for (const auto& lr : pairs[k].levels) {
      if (lr.level < 0 || lr.level >= levels) continue;
      row.iterations_per_level[lr.level] += lr.iterations / np;
      if (is_reference || k >= reference.size() || lr.skipped) continue;
      for (const auto& ref : reference[k].levels) {
        if (ref.level == lr.level && !ref.skipped && ref.f_i > 0 && ref.f_d > 0) {
          gap[lr.level] += (lr.f_i - ref.f_i) / ref.f_i;
          ratio[lr.level] += lr.f_d / ref.f_d;
          ++gap_n[lr.level];
        }
      }
    }
  }
  if (!is_reference) {
    for (int l = 0; l < levels; ++l) {
      row.f_i_gap.push_back(gap_n[l] ? gap[l] / gap_n[l] : 0.0);
      row.f_d_ratio.push_back(gap_n[l] ? ratio[l] / gap_n[l] : 0.0);
    }
  }
  return row;
}

}  // namespace

std::vector<ProfileRow> run_profile(const ProfileOptions& o) {
  if (o.repetitions < 1 || o.repetitions > 100) {
    throw Error("profile: repetitions must be in 1..100, got " + std::to_string(o.repetitions));
  }
  std::vector<MethodSpec> methods = o.methods;
  // The reference is single with Gauss-Newton: moved to the front when listed, added when not,
  // so it is timed and printed once.
  const auto is_reference = [](const MethodSpec& m) {
    return m.method == "single" && (m.backend.empty() || m.backend == "gn");
  };
  const auto listed = std::find_if(methods.begin(), methods.end(), is_reference);
  if (listed == methods.end()) {
    methods.insert(methods.begin(), MethodSpec{"single", "gn"});
  } else {
    std::rotate(methods.begin(), listed, listed + 1);
  }
  std::vector<RunRequest> requests;
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
    // Each method's window as its runs will check it, before any run.
    odometry::validate(with_frame_window(req.tracker, req.first_frame, req.max_frames));
    req.progress = o.progress;
    requests.push_back(req);
  }
  // Untimed warm-up: the first run pays for the page cache, the allocator and the thread
  // pools, which made the reference (always first) look slower than itself.
  try {
    run_sequence(requests.front());
  } catch (const Error&) {
    // its error is reported by the timed runs below
  }
  // Repetitions with the methods' order rotated, so no method is always first or last.
  const std::size_t m = methods.size();
  std::vector<std::vector<RunOutcome>> runs(m);
  std::vector<std::string> notes(m);
  for (int r = 0; r < o.repetitions; ++r) {
    for (std::size_t i = 0; i < m; ++i) {
      const std::size_t k = (i + std::size_t(r)) % m;
      if (!notes[k].empty()) continue;
      try {
        runs[k].push_back(run_sequence(requests[k]));
      } catch (const Error& e) {
        notes[k] = e.what();
      }
    }
  }
  std::vector<ProfileRow> rows;
  const std::vector<odometry::PairResult> reference =
      runs.front().empty() ? std::vector<odometry::PairResult>{} : runs.front().front().pairs;
  for (std::size_t k = 0; k < m; ++k) {
    ProfileRow row;
    row.method = methods[k].method;
    row.backend = effective_backend(requests[k].tracker);
    row.note = notes[k];
    rows.push_back(
        row_of(row, notes[k].empty() ? runs[k] : std::vector<RunOutcome>{}, reference, k == 0, o.tracker.levels));
  }
  return rows;
}

std::string write_profile(const std::vector<ProfileRow>& rows, const std::string& dir) {
  odometry::io::create_output_directory(dir);
  std::vector<std::string> phases = kPhases;
  for (const auto& r : rows) {
    for (const auto& [name, ms] : r.phase_ms) {
      if (std::find(phases.begin(), phases.end(), name) == phases.end()) phases.push_back(name);
    }
  }
  std::ostringstream md, csv;
  // Per-phase times depend on the kernels' instruction set: name it beside them.
  const std::string kernels = odometry::to_string(odometry::default_kernels().isa);
  md << "Per-pixel kernels: " << kernels
     << " (the best instruction set of this CPU; avx2 and avx512vl give "
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
      if (r.f_i_gap.empty())
        csv << ",,";
      else
        csv << "," << r.f_i_gap[l] << "," << r.f_d_ratio[l];
    }
    csv << "\n" << std::defaultfloat;
    md << std::defaultfloat;
    j.push_back({{"method", r.method},
                 {"backend", r.backend},
                 {"pairs", r.pairs},
                 {"total_ms", r.total_ms},
                 {"phase_ms", r.phase_ms},
                 {"iterations_per_level", r.iterations_per_level},
                 {"median_ms", r.median_ms},
                 {"q1_ms", r.q1_ms},
                 {"q3_ms", r.q3_ms},
                 {"repetitions", r.repetitions},
                 {"f_i_gap_per_level", r.f_i_gap},
                 {"f_d_ratio_per_level", r.f_d_ratio},
                 {"note", r.note},
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
    for (int l = levels - 1; l >= 0; --l)
      md << " " << std::fixed << std::setprecision(1) << r.iterations_per_level[l] << " |";
    for (int l = levels - 1; l >= 0; --l) {
      if (r.f_i_gap.empty())
        md << " (reference) | (reference) |";
      else
        md << " " << std::showpos << std::setprecision(4) << r.f_i_gap[l] << std::noshowpos << " | " << r.f_d_ratio[l]
           << " |";
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
