#include "experiments/loso.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <sstream>

#include "experiments/result_table.h"
#include "experiments/sequence_runner.h"
#include "experiments/tracker_option_table.h"
#include "odometry/io/atomic_file.h"
#include "odometry/io/metrics.h"
#include "solvers/error.h"

namespace bivo::experiments {
namespace {

double ratio(double a, double b) { return b > 0.0 ? a / b : std::numeric_limits<double>::infinity(); }

// The worse of the translational and rotational ratio of `run` to `ref`.
double worst_ratio(const LosoRun& run, const LosoRun& ref) {
  return std::max(ratio(run.rpe_trans, ref.rpe_trans), ratio(run.rpe_rot, ref.rpe_rot));
}

double max_of(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); }

std::string run_name(const LosoRun& r, const std::string& parameter) {
  std::ostringstream s;
  s << r.method;
  if (r.has_value) s << " " << parameter << "=" << r.value;
  return s.str();
}

}  // namespace

void set_loso_parameter(odometry::TrackerOptions& o, const std::string& name, double v) {
  const TrackerOption* option = find_tracker_option_by_key(name);
  if (!option) option = find_tracker_option_by_key("policy." + name);
  const bool numeric = option && (option->type == OptionType::kNumber || option->type == OptionType::kInteger ||
                                  option->type == OptionType::kOptionalNumber);
  if (!numeric) {
    std::string valid;
    for (const TrackerOption& t : tracker_option_table()) {
      if (t.type == OptionType::kNumber || t.type == OptionType::kInteger || t.type == OptionType::kOptionalNumber)
        valid += (valid.empty() ? "" : ", ") + t.key;
    }
    throw Error("loso: '" + name + "' is not a numeric tracker option (valid: " + valid +
                "; a policy.* key may be given without 'policy.')");
  }
  nlohmann::json value = v;
  if (option->type == OptionType::kInteger && std::isfinite(v) && v == std::floor(v) && std::fabs(v) < 1e15)
    value = static_cast<long long>(v);
  try {
    apply_tracker_option(*option, value, o);
  } catch (const Error& e) {
    throw Error(std::string("loso: ") + e.what());
  }
}

std::vector<LosoRun> loso_units(const LosoOptions& o) {
  if (o.sequences.size() < 2)
    throw Error("loso: needs at least 2 sequences (one is held out), got " + std::to_string(o.sequences.size()));
  if (o.grid.empty()) throw Error("loso: the grid of '" + o.parameter + "' is empty");
  odometry::TrackerOptions probe = o.tracker;
  for (double v : o.grid) set_loso_parameter(probe, o.parameter, v);  // a bad name or value fails before any run
  if (!(o.cost_budget >= 0.0 && std::isfinite(o.cost_budget))) {
    std::ostringstream got;
    got << o.cost_budget;
    throw Error("loso: the cost budget must be finite and >= 0 (0: none), got " + got.str());
  }
  if (o.cost_budget > 0.0 && o.cost_method != o.reference &&
      std::find(o.methods.begin(), o.methods.end(), o.cost_method) == o.methods.end()) {
    throw Error("loso: the cost budget is in units of '" + o.cost_method +
                "', which is neither the reference nor among the methods run beside");
  }
  std::vector<LosoRun> units;
  for (int s = 0; s < static_cast<int>(o.sequences.size()); ++s) {
    LosoRun r;
    r.sequence = s;
    r.method = o.reference;
    units.push_back(r);
    for (double v : o.grid) {
      r.method = o.method;
      r.has_value = true;
      r.value = v;
      units.push_back(r);
    }
    r.has_value = false;
    for (const std::string& m : o.methods) {
      r.method = m;
      units.push_back(r);
    }
  }
  return units;
}

void run_loso_unit(const LosoOptions& o, LosoRun& r) {
  const std::string& dir = o.sequences.at(r.sequence);
  RunRequest req;
  req.sequence_dir = dir;
  req.tracker = o.tracker;
  req.tracker.method = r.method;
  req.tracker.backend = "";
  if (r.has_value) set_loso_parameter(req.tracker, o.parameter, r.value);
  req.first_frame = o.first_frame;
  req.max_frames = o.max_frames;
  req.progress = o.progress;
  r.sequence_name = std::filesystem::path(dir).filename().string();
  req.label = r.sequence_name + " " + run_name(r, o.parameter);
  try {
    const RunOutcome run = run_sequence(req);
    if (!run.groundtruth) throw Error("loso: sequence '" + dir + "' has no groundtruth.txt");
    const auto rpe = odometry::io::relative_pose_error(*run.groundtruth, run.trajectory);
    if (rpe.pairs.empty()) throw Error("loso: sequence '" + dir + "' is shorter than one RPE window (1 s)");
    r.rpe_trans = rpe.trans_rmse;
    r.rpe_rot = rpe.rot_rmse_deg;
    r.median_cpu_ms = run.median_cpu_ms;
    for (const auto& p : run.pairs) {
      if (!p.error) continue;
      r.pair_trans.push_back(p.error->translation_m);
      r.pair_rot.push_back(p.error->rotation_deg);
    }
    r.ok = true;
  } catch (const Error& e) {
    r.error = e.what();
  }
}

LosoResult assemble_loso(const LosoOptions& o, std::vector<LosoRun> runs) {
  LosoResult out;
  out.options = o;
  out.runs = std::move(runs);
  const int n = static_cast<int>(o.sequences.size());
  std::vector<const LosoRun*> ref(n, nullptr);
  for (const LosoRun& r : out.runs) {
    if (!r.has_value && r.method == o.reference) ref[r.sequence] = &r;
  }
  for (int s = 0; s < n; ++s) {
    if (!ref[s] || !ref[s]->ok) {
      throw Error("loso: the reference run (" + o.reference + ") on '" + o.sequences[s] +
                  "' failed: " + (ref[s] ? ref[s]->error : std::string("missing")));
    }
  }
  const auto at = [&](int s, double v) -> const LosoRun* {
    for (const LosoRun& r : out.runs) {
      if (r.sequence == s && r.has_value && r.value == v && r.method == o.method) return &r;
    }
    return nullptr;
  };
  const auto fixed = [&](int s, const std::string& method) -> const LosoRun* {
    for (const LosoRun& r : out.runs) {
      if (r.sequence == s && !r.has_value && r.method == method) return &r;
    }
    return nullptr;
  };
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const bool budget = o.cost_budget > 0.0;
  for (int s = 0; budget && s < n; ++s) {
    const LosoRun* c = fixed(s, o.cost_method);
    if (!c || !c->ok) {
      throw Error("loso: the cost method's run (" + o.cost_method + ") on '" + o.sequences[s] +
                  "' failed, so the cost budget is undefined: " + (c ? c->error : std::string("missing")));
    }
  }
  for (int h = 0; h < n; ++h) {
    LosoRow row;
    row.sequence = ref[h]->sequence_name;
    row.reference = ref[h];
    // Per grid value over the other sequences: the worst ratio, the sum of the ratios' logs
    // and the CPU per pair relative to the cost method's.
    struct Score {
      double value, worst = 0.0, log_sum = 0.0, cost = 0.0;
    };
    std::vector<Score> scores;
    for (double v : o.grid) {
      Score sc{v};
      double cpu = 0.0, cpu_of_cost_method = 0.0;
      for (int s = 0; s < n; ++s) {
        if (s == h) continue;
        const LosoRun* r = at(s, v);
        const double w = r && r->ok ? worst_ratio(*r, *ref[s]) : kInf;
        sc.worst = std::max(sc.worst, w);
        sc.log_sum += std::log(w);
        cpu += r && r->ok ? r->median_cpu_ms : kInf;
        if (budget) cpu_of_cost_method += fixed(s, o.cost_method)->median_cpu_ms;
      }
      sc.cost = budget ? cpu / cpu_of_cost_method : 0.0;
      scores.push_back(sc);
    }
    // A parameter that does not move the worst sequence ties there: the geometric mean of
    // the same ratios decides, then the first grid value.
    const auto more_accurate = [](const Score& a, const Score& b) {
      return a.worst < b.worst || (a.worst == b.worst && a.log_sum < b.log_sum);
    };
    const auto within = [&](const Score& sc) { return !budget || sc.cost <= o.cost_budget; };
    const Score* best = nullptr;
    for (const Score& sc : scores) {
      if (within(sc) && (!best || more_accurate(sc, *best))) best = &sc;
    }
    if (!best) {  // no value keeps within the budget: the cheapest
      for (const Score& sc : scores) {
        if (!best || sc.cost < best->cost || (sc.cost == best->cost && more_accurate(sc, *best))) best = &sc;
      }
    }
    row.chosen = best->value;
    row.train_worst = best->worst;
    row.train_cost = best->cost;
    row.held_out = at(h, row.chosen);
    for (const std::string& m : o.methods) row.others.push_back(fixed(h, m));
    out.rows.push_back(row);
  }
  return out;
}

LosoResult run_loso(const LosoOptions& o) {
  std::vector<LosoRun> runs = loso_units(o);
  for (LosoRun& r : runs) run_loso_unit(o, r);
  return assemble_loso(o, std::move(runs));
}

std::string write_loso(const LosoResult& result, const std::string& dir) {
  const LosoOptions& o = result.options;
  const auto cell = [](const LosoRun* r, const LosoRun* ref) {
    std::ostringstream c;
    if (!r || !r->ok) return std::string("failed");
    c << std::fixed << std::setprecision(4) << r->rpe_trans << " / " << std::setprecision(3) << r->rpe_rot << " ("
      << std::setprecision(2) << ratio(r->rpe_trans, ref->rpe_trans) << "x / " << ratio(r->rpe_rot, ref->rpe_rot)
      << "x; max pair " << max_of(r->pair_rot) << " deg)";
    return c.str();
  };
  std::ostringstream md, csv, runs_csv, pairs_csv;
  md << "Held-out RPE trans [m/s] / rot [deg/s] (ratio to " << o.reference << "; largest per-pair rotation error); "
     << o.method << "'s " << o.parameter << " chosen on the other sequences.\n\n| held out | " << o.parameter
     << " chosen | worst ratio on the others |";
  const bool budget = o.cost_budget > 0.0;
  if (budget) md << " CPU per pair on the others (x " << o.cost_method << "; budget " << o.cost_budget << ") |";
  md << " " << o.reference << " | " << o.method << " |";
  for (const std::string& m : o.methods) md << " " << m << " |";
  md << "\n|---|---:|---:|" << (budget ? "---:|" : "") << "---:|---:|";
  for (std::size_t k = 0; k < o.methods.size(); ++k) md << "---:|";
  md << "\n";
  csv << "sequence,chosen,train_worst,ref_trans,ref_rot,trans,rot,trans_ratio,rot_ratio,max_pair_rot,ref_max_pair_"
         "rot,train_cost\n";
  for (const LosoRow& row : result.rows) {
    const LosoRun& ref = *row.reference;
    md << "| " << row.sequence << " | " << row.chosen << " | " << std::fixed << std::setprecision(3) << row.train_worst
       << " | ";
    if (budget) md << std::setprecision(2) << row.train_cost << " | ";
    md << std::setprecision(4) << ref.rpe_trans << " / " << std::setprecision(3) << ref.rpe_rot << " (max pair "
       << std::setprecision(2) << max_of(ref.pair_rot) << " deg) | " << cell(row.held_out, &ref) << " |";
    for (const LosoRun* r : row.others) md << " " << cell(r, &ref) << " |";
    md << "\n";
    md.unsetf(std::ios::fixed);
    const bool ok = row.held_out && row.held_out->ok;
    csv << csv_field(row.sequence) << "," << std::setprecision(10) << row.chosen << "," << row.train_worst << ","
        << ref.rpe_trans << "," << ref.rpe_rot << "," << (ok ? row.held_out->rpe_trans : NAN) << ","
        << (ok ? row.held_out->rpe_rot : NAN) << "," << (ok ? ratio(row.held_out->rpe_trans, ref.rpe_trans) : NAN)
        << "," << (ok ? ratio(row.held_out->rpe_rot, ref.rpe_rot) : NAN) << ","
        << (ok ? max_of(row.held_out->pair_rot) : NAN) << "," << max_of(ref.pair_rot) << ","
        << (budget ? row.train_cost : NAN) << "\n";
  }
  runs_csv << "sequence,method,value,ok,rpe_trans,rpe_rot,median_cpu_ms,max_pair_trans,max_pair_rot,error\n";
  pairs_csv << "sequence,method,value,pair,trans_err_m,rot_err_deg\n";
  for (const LosoRun& r : result.runs) {
    const std::string value = r.has_value ? (std::ostringstream() << std::setprecision(10) << r.value).str() : "";
    runs_csv << csv_field(r.sequence_name) << "," << r.method << "," << value << "," << r.ok << ","
             << std::setprecision(10) << r.rpe_trans << "," << r.rpe_rot << "," << r.median_cpu_ms << ","
             << max_of(r.pair_trans) << "," << max_of(r.pair_rot) << "," << csv_field(r.error) << "\n";
    for (std::size_t k = 0; k < r.pair_rot.size(); ++k) {
      pairs_csv << csv_field(r.sequence_name) << "," << r.method << "," << value << "," << k << "," << r.pair_trans[k]
                << "," << r.pair_rot[k] << "\n";
    }
  }
  odometry::io::create_output_directory(dir);
  odometry::io::StagedOutputs out;
  const std::string base = (std::filesystem::path(dir) / "").string();
  const std::string text = md.str();
  out.add(base + "loso.md", [&](std::ostream& f) { f << text; });
  out.add(base + "loso.csv", [&](std::ostream& f) { f << csv.str(); });
  out.add(base + "runs.csv", [&](std::ostream& f) { f << runs_csv.str(); });
  out.add(base + "pairs.csv", [&](std::ostream& f) { f << pairs_csv.str(); });
  out.commit();
  return text;
}

}  // namespace bivo::experiments
