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
#include "experiments/trajectory_evaluation.h"
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

// The tracker option `name` names (a policy key also without "policy."), when numeric.
const TrackerOption* numeric_option(const std::string& name) {
  const TrackerOption* option = find_tracker_option_by_key(name);
  if (!option) option = find_tracker_option_by_key("policy." + name);
  const bool numeric = option && (option->type == OptionType::kNumber || option->type == OptionType::kInteger ||
                                  option->type == OptionType::kOptionalNumber);
  return numeric ? option : nullptr;
}

std::string run_name(const LosoRun& r, const LosoOptions& o) {
  std::ostringstream s;
  s << r.method;
  for (std::size_t k = 0; k < r.values.size(); ++k) s << " " << o.parameters.at(k).name << "=" << r.values[k];
  if (r.finest_level >= 0) s << " finest level " << r.finest_level;
  return s.str();
}

// The finest levels of the runs: the pooled ones, or -1 (the tracker's) alone.
std::vector<int> run_levels(const LosoOptions& o) {
  return o.finest_levels.empty() ? std::vector<int>{-1} : o.finest_levels;
}

std::string at_level(int level) { return level < 0 ? "" : " at finest level " + std::to_string(level); }

}  // namespace

void set_loso_parameter(odometry::TrackerOptions& o, const std::string& name, double v) {
  const TrackerOption* option = numeric_option(name);
  if (!option) {
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

std::vector<std::vector<double>> loso_settings(const LosoOptions& o) {
  if (o.parameters.empty()) return {};
  std::vector<std::vector<double>> settings = {{}};
  for (const LosoParameter& p : o.parameters) {
    std::vector<std::vector<double>> longer;
    for (const std::vector<double>& head : settings) {
      for (double v : p.grid) {
        longer.push_back(head);
        longer.back().push_back(v);
      }
    }
    settings = std::move(longer);
  }
  return settings;
}

std::vector<LosoRun> loso_units(const LosoOptions& o) {
  if (o.sequences.size() < 2)
    throw Error("loso: needs at least 2 sequences (one is held out), got " + std::to_string(o.sequences.size()));
  if (o.parameters.empty()) throw Error("loso: no --parameter to choose");
  for (std::size_t k = 0; k < o.parameters.size(); ++k) {
    const LosoParameter& p = o.parameters[k];
    if (p.grid.empty()) throw Error("loso: the --grid of '" + p.name + "' is empty");
    odometry::TrackerOptions probe = o.tracker;
    for (double v : p.grid) set_loso_parameter(probe, p.name, v);  // a bad name or value fails before any run
    for (std::size_t e = 0; e < k; ++e) {  // one option under two names would be set twice per run
      const LosoParameter& earlier = o.parameters[e];
      const std::string& key = numeric_option(p.name)->key;
      if (numeric_option(earlier.name)->key != key) continue;
      throw Error("loso: --parameter '" + key + "' is given twice" +
                  (earlier.name == p.name ? std::string() : " (as '" + earlier.name + "' and '" + p.name + "')"));
    }
  }
  for (const LosoParameter& p : o.parameters) {
    if (!o.finest_levels.empty() && numeric_option(p.name)->key == "finest_level")
      throw Error("loso: --parameter finest_level and --finest-levels both set the finest level; give one");
  }
  for (std::size_t k = 0; k < o.finest_levels.size(); ++k) {
    const int level = o.finest_levels[k];
    if (level < 0 || level >= o.tracker.levels) {
      throw Error("loso: --finest-levels " + std::to_string(level) + " is not a level of the pyramid (0.." +
                  std::to_string(o.tracker.levels - 1) + " with --levels " + std::to_string(o.tracker.levels) + ")");
    }
    if (std::find(o.finest_levels.begin(), o.finest_levels.begin() + k, level) != o.finest_levels.begin() + k)
      throw Error("loso: --finest-levels lists " + std::to_string(level) + " twice");
  }
  if (!(o.cost_budget >= 0.0 && std::isfinite(o.cost_budget))) {
    std::ostringstream got;
    got << o.cost_budget;
    throw Error("loso: the cost budget must be finite and >= 0 (0: none), got " + got.str());
  }
  if (!(o.acceptable_ratio >= 0.0 && std::isfinite(o.acceptable_ratio))) {
    std::ostringstream got;
    got << o.acceptable_ratio;
    throw Error("loso: the acceptable ratio must be finite and >= 0 (0: the smallest worst ratio decides), got " +
                got.str());
  }
  if (o.cost_budget > 0.0 && o.cost_method != o.reference &&
      std::find(o.methods.begin(), o.methods.end(), o.cost_method) == o.methods.end()) {
    throw Error("loso: the cost budget is in units of '" + o.cost_method +
                "', which is neither the reference nor among the methods run beside");
  }
  const std::vector<std::vector<double>> settings = loso_settings(o);
  std::vector<LosoRun> units;
  for (int s = 0; s < static_cast<int>(o.sequences.size()); ++s) {
    for (int level : run_levels(o)) {
      LosoRun r;
      r.sequence = s;
      r.finest_level = level;
      r.method = o.reference;
      units.push_back(r);
      r.method = o.method;
      for (const std::vector<double>& setting : settings) {
        r.values = setting;
        units.push_back(r);
      }
      r.values.clear();
      for (const std::string& m : o.methods) {
        r.method = m;
        units.push_back(r);
      }
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
  for (std::size_t k = 0; k < r.values.size(); ++k)
    set_loso_parameter(req.tracker, o.parameters.at(k).name, r.values[k]);
  if (r.finest_level >= 0) req.tracker.finest_level = r.finest_level;
  req.first_frame = o.first_frame;
  req.max_frames = o.max_frames;
  req.progress = o.progress;
  r.sequence_name = std::filesystem::path(dir).filename().string();
  req.label = r.sequence_name + " " + run_name(r, o);
  try {
    const RunOutcome run = run_sequence(req);
    if (!run.groundtruth) throw Error("loso: sequence '" + dir + "' has no groundtruth.txt");
    std::string why;  // a sequence too short to score cannot be held out or chosen on
    const auto rpe = rpe_if_long_enough(*run.groundtruth, run.trajectory, o.rpe_delta, why);
    if (!rpe) throw Error("loso: sequence '" + dir + "': " + why);
    r.rpe_trans = rpe->trans_rmse;
    r.rpe_rot = rpe->rot_rmse_deg;
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
  const std::vector<int> levels = run_levels(o);
  const int nl = static_cast<int>(levels.size());
  // The run of a method (at a setting) on a sequence at a level; the first of its kind.
  const auto find_run = [&](int s, int level, const std::string& method,
                            const std::vector<double>& values) -> const LosoRun* {
    for (const LosoRun& r : out.runs) {
      if (r.sequence == s && r.finest_level == level && r.method == method && r.values == values) return &r;
    }
    return nullptr;
  };
  // ref[s][l]: the reference on sequence s at levels[l] (the last of its kind, as ever).
  std::vector<std::vector<const LosoRun*>> ref(n, std::vector<const LosoRun*>(nl, nullptr));
  for (const LosoRun& r : out.runs) {
    const auto l = std::find(levels.begin(), levels.end(), r.finest_level) - levels.begin();
    if (r.values.empty() && r.method == o.reference && r.sequence >= 0 && r.sequence < n && l < nl)
      ref[r.sequence][l] = &r;
  }
  for (int s = 0; s < n; ++s) {
    for (int l = 0; l < nl; ++l) {
      if (!ref[s][l] || !ref[s][l]->ok) {
        throw Error("loso: the reference run (" + o.reference + ") on '" + o.sequences[s] + "'" + at_level(levels[l]) +
                    " failed: " + (ref[s][l] ? ref[s][l]->error : std::string("missing")));
      }
    }
  }
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const bool budget = o.cost_budget > 0.0;
  for (int s = 0; budget && s < n; ++s) {
    for (int level : levels) {
      const LosoRun* c = find_run(s, level, o.cost_method, {});
      if (!c || !c->ok) {
        throw Error("loso: the cost method's run (" + o.cost_method + ") on '" + o.sequences[s] + "'" +
                    at_level(level) +
                    " failed, so the cost budget is undefined: " + (c ? c->error : std::string("missing")));
      }
    }
  }
  const std::vector<std::vector<double>> settings = loso_settings(o);
  for (int h = 0; h < n; ++h) {
    // Per setting over the other sequences at every level: the worst ratio, the sum of the
    // ratios' logs and, per level, the CPU per pair relative to the cost method's, the
    // geometric mean of the per-sequence ratios (`cost`: the largest of them). Per sequence, so
    // that a cost both methods share (a sequence that is slow for both) dilutes nothing.
    struct Score {
      const std::vector<double>* setting;
      double worst = 0.0, log_sum = 0.0, cost = 0.0;
      std::vector<double> level_cost;
    };
    std::vector<Score> scores;
    for (const std::vector<double>& setting : settings) {
      Score sc{&setting, 0.0, 0.0, 0.0, {}};
      for (int l = 0; l < nl; ++l) {
        double log_cost_sum = 0.0;
        for (int s = 0; s < n; ++s) {
          if (s == h) continue;
          const LosoRun* r = find_run(s, levels[l], o.method, setting);
          const double w = r && r->ok ? worst_ratio(*r, *ref[s][l]) : kInf;
          sc.worst = std::max(sc.worst, w);
          sc.log_sum += std::log(w);
          if (budget) {
            const double cpu = r && r->ok ? r->median_cpu_ms : kInf;
            log_cost_sum += std::log(cpu / find_run(s, levels[l], o.cost_method, {})->median_cpu_ms);
          }
        }
        const double cost = budget ? std::exp(log_cost_sum / (n - 1)) : 0.0;
        sc.level_cost.push_back(cost);
        sc.cost = l == 0 ? cost : std::max(sc.cost, cost);
      }
      scores.push_back(sc);
    }
    // Acceptable settings first, by geometric mean; the others by worst ratio, a tie (a
    // parameter that does not move the worst sequence) by geometric mean; then the first.
    const auto acceptable = [&](const Score& sc) { return sc.worst <= o.acceptable_ratio; };
    const auto more_accurate = [&](const Score& a, const Score& b) {
      if (acceptable(a) != acceptable(b)) return acceptable(a);
      if (acceptable(a)) return a.log_sum < b.log_sum || (a.log_sum == b.log_sum && a.worst < b.worst);
      return a.worst < b.worst || (a.worst == b.worst && a.log_sum < b.log_sum);
    };
    const auto within = [&](const Score& sc) { return !budget || sc.cost <= o.cost_budget; };
    const Score* best = nullptr;
    for (const Score& sc : scores) {
      if (within(sc) && (!best || more_accurate(sc, *best))) best = &sc;
    }
    if (!best) {  // no setting keeps within the budget at every level: the cheapest
      for (const Score& sc : scores) {
        if (!best || sc.cost < best->cost || (sc.cost == best->cost && more_accurate(sc, *best))) best = &sc;
      }
    }
    for (int l = 0; l < nl; ++l) {
      LosoRow row;
      row.sequence = ref[h][l]->sequence_name;
      row.finest_level = levels[l];
      row.reference = ref[h][l];
      row.chosen = *best->setting;
      row.train_worst = best->worst;
      row.train_mean = std::exp(best->log_sum / ((n - 1) * nl));
      row.train_cost = best->level_cost[l];
      row.held_out = find_run(h, levels[l], o.method, row.chosen);
      for (const std::string& m : o.methods) row.others.push_back(find_run(h, levels[l], m, {}));
      out.rows.push_back(row);
    }
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
  // Several parameters name their columns "chosen:<name>" (loso.csv) and "value:<name>"
  // (runs.csv, pairs.csv); one keeps "chosen" and "value". Pooled levels add a finest-level
  // column, and each held-out sequence has a row per level.
  const bool several = o.parameters.size() > 1, pooled = !o.finest_levels.empty();
  const auto columns = [&](const std::string& name) {
    std::string out;
    for (const LosoParameter& p : o.parameters) out += (out.empty() ? "" : ",") + name + (several ? ":" + p.name : "");
    return out;
  };
  const auto listed = [](const std::vector<std::string>& items) {  // "a", "a and b", "a, b and c"
    std::string out;
    for (std::size_t k = 0; k < items.size(); ++k)
      out += (k == 0 ? "" : k + 1 == items.size() ? " and " : ", ") + items[k];
    return out;
  };
  std::vector<std::string> names, levels;
  for (const LosoParameter& p : o.parameters) names.push_back(p.name);
  for (int level : o.finest_levels) levels.push_back(std::to_string(level));
  std::ostringstream md, csv, runs_csv, pairs_csv;
  md << "Held-out RPE trans [" << rpe_unit("m", o.rpe_delta) << "] / rot [" << rpe_unit("deg", o.rpe_delta)
     << "] (ratio to " << o.reference << "; largest per-pair rotation error); " << o.method << "'s " << listed(names)
     << (several ? " chosen together" : " chosen") << " on the other sequences";
  if (pooled) md << ", at finest levels " << listed(levels) << " at once";
  if (o.acceptable_ratio > 0.0) {
    md << "; of the settings within " << o.acceptable_ratio << "x " << o.reference
       << " there, the smallest geometric mean of the per-sequence worst ratios";
  }
  md << ".\n\n| held out |" << (pooled ? " finest level |" : "");
  for (const std::string& name : names) md << " " << name << " chosen |";
  md << " worst ratio on the others | geometric mean there |";
  const bool budget = o.cost_budget > 0.0;
  if (budget) md << " CPU per pair on the others (x " << o.cost_method << "; budget " << o.cost_budget << ") |";
  md << " " << o.reference << " | " << o.method << " |";
  for (const std::string& m : o.methods) md << " " << m << " |";
  md << "\n|---|" << (pooled ? "---:|" : "");
  for (std::size_t k = 0; k < names.size(); ++k) md << "---:|";
  md << "---:|---:|" << (budget ? "---:|" : "") << "---:|---:|";
  for (std::size_t k = 0; k < o.methods.size(); ++k) md << "---:|";
  md << "\n";
  csv << "sequence," << (pooled ? "finest_level," : "") << columns("chosen")
      << ",train_worst,ref_trans,ref_rot,trans,rot,trans_ratio,rot_ratio,max_pair_rot,ref_max_pair_rot,train_cost,"
         "train_mean\n";
  for (const LosoRow& row : result.rows) {
    const LosoRun& ref = *row.reference;
    // A single parameter's values are printed as they always were (from the second row on at
    // the previous row's precision, 2 digits); several or pooled: at 6.
    if (several || pooled) md << std::setprecision(6);
    md << "| " << row.sequence << " |";
    if (pooled) md << " " << row.finest_level << " |";
    for (double v : row.chosen) md << " " << v << " |";
    md << " " << std::fixed << std::setprecision(3) << row.train_worst << " | " << row.train_mean << " | ";
    if (budget) md << std::setprecision(2) << row.train_cost << " | ";
    md << std::setprecision(4) << ref.rpe_trans << " / " << std::setprecision(3) << ref.rpe_rot << " (max pair "
       << std::setprecision(2) << max_of(ref.pair_rot) << " deg) | " << cell(row.held_out, &ref) << " |";
    for (const LosoRun* r : row.others) md << " " << cell(r, &ref) << " |";
    md << "\n";
    md.unsetf(std::ios::fixed);
    const bool ok = row.held_out && row.held_out->ok;
    csv << csv_field(row.sequence) << ",";
    if (pooled) csv << row.finest_level << ",";
    csv << std::setprecision(10);
    for (double v : row.chosen) csv << v << ",";
    csv << row.train_worst << "," << ref.rpe_trans << "," << ref.rpe_rot << "," << (ok ? row.held_out->rpe_trans : NAN)
        << "," << (ok ? row.held_out->rpe_rot : NAN) << ","
        << (ok ? ratio(row.held_out->rpe_trans, ref.rpe_trans) : NAN) << ","
        << (ok ? ratio(row.held_out->rpe_rot, ref.rpe_rot) : NAN) << "," << (ok ? max_of(row.held_out->pair_rot) : NAN)
        << "," << max_of(ref.pair_rot) << "," << (budget ? row.train_cost : NAN) << "," << row.train_mean << "\n";
  }
  const std::string level_column = pooled ? "finest_level," : "";
  runs_csv << "sequence,method," << columns("value") << "," << level_column
           << "ok,rpe_trans,rpe_rot,median_cpu_ms,max_pair_trans,max_pair_rot,error\n";
  pairs_csv << "sequence,method," << columns("value") << "," << level_column << "pair,trans_err_m,rot_err_deg\n";
  for (const LosoRun& r : result.runs) {
    std::ostringstream setting;  // the values' columns, empty for the reference and the fixed methods
    for (std::size_t k = 0; k < o.parameters.size(); ++k) {
      setting << (k == 0 ? "" : ",") << std::setprecision(10);
      if (k < r.values.size()) setting << r.values[k];
    }
    if (pooled) setting << "," << r.finest_level;
    const std::string value = setting.str();
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
