// Study description, its JSON, hash, units and shards (study.h).
#include "experiments/study/study.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <numeric>
#include <set>

#include "experiments/json_object_reader.h"
#include "experiments/tracker_config.h"
#include "odometry/io/atomic_file.h"
#include "odometry/io/json_file.h"
#include "solvers/error.h"

namespace bivo::experiments {
namespace {

using json = nlohmann::json;

constexpr int kFormatVersion = 1;

// Every key of a study file is required (json_object_reader.h).
using Reader = JsonObjectReader;

json methods_json(const std::vector<MethodSpec>& methods) {
  json j = json::array();
  for (const auto& m : methods) j.push_back(method_spec_text(m));
  return j;
}

// The parts: what the units compute (hashed).
json parts_json(const Study& s) {
  json j = json::object();
  j["kind"] = s.kind;
  j["tracker"] = tracker_options_to_json(s.tracker);
  if (s.table) {
    j["table"] = {{"sequences", s.table->sequences},
                  {"methods", methods_json(s.table->methods)},
                  {"first_frame", s.table->first_frame},
                  {"max_frames", s.table->max_frames}};
    // Written only when not the default, so the hashes of studies planned before stay valid.
    if (s.table->rpe_delta != 1.0) j["table"]["rpe_delta"] = s.table->rpe_delta;
  }
  if (s.sweep) {
    j["sweep"] = {{"sequences", s.sweep->sequences},     {"lambdas", s.sweep->lambdas},
                  {"epsilons", s.sweep->epsilons},       {"epsilon_backend", s.sweep->epsilon_backend},
                  {"first_frame", s.sweep->first_frame}, {"max_frames", s.sweep->max_frames}};
    if (s.sweep->rpe_delta != 1.0) j["sweep"]["rpe_delta"] = s.sweep->rpe_delta;
  }
  if (s.pareto) {
    const auto& o = s.pareto->options;
    json pairs = json::array();
    for (const auto& p : s.pareto->pairs) pairs.push_back({{"sequence", p.sequence_dir}, {"pair", p.pair}});
    j["pareto"] = {{"level", o.level},           {"points", o.points},   {"lambda_min", o.lambda_min},
                   {"lambda_max", o.lambda_max}, {"methods", o.methods}, {"pairs", pairs}};
    if (!o.backend.empty()) j["pareto"]["backend"] = o.backend;  // absent: the default, as planned before
  }
  if (s.loso) {
    const LosoOptions& o = *s.loso;
    j["loso"] = {{"sequences", o.sequences}, {"method", o.method},           {"reference", o.reference},
                 {"methods", o.methods},     {"first_frame", o.first_frame}, {"max_frames", o.max_frames}};
    // One parameter as "parameter" and "grid", as planned before several could be chosen
    // together (the same hash); several as "parameters": [{"parameter", "grid"}, ...].
    if (o.parameters.size() == 1) {
      j["loso"]["parameter"] = o.parameters[0].name;
      j["loso"]["grid"] = o.parameters[0].grid;
    } else {
      j["loso"]["parameters"] = json::array();
      for (const LosoParameter& p : o.parameters)
        j["loso"]["parameters"].push_back({{"parameter", p.name}, {"grid", p.grid}});
    }
    if (!o.finest_levels.empty()) j["loso"]["finest_levels"] = o.finest_levels;  // absent: the tracker's
    if (o.rpe_delta != 1.0) j["loso"]["rpe_delta"] = o.rpe_delta;                // absent: 1 s
    j["loso"]["acceptable_ratio"] = o.acceptable_ratio;
    if (o.cost_budget > 0.0) {  // absent: none, as planned before budgets existed
      j["loso"]["cost_budget"] = o.cost_budget;
      j["loso"]["cost_method"] = o.cost_method;
    }
  }
  return j;
}

// A unit id component: what the file system and a shell accept unquoted.
std::string token(const std::string& text) {
  std::string out;
  for (char c : text)
    out += (std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '_' || c == '=' || c == '+')
               ? c
               : '_';
  return out;
}

std::string number_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// What would make a LOSO run fail for its options rather than its data, refused before any
// run: too few sequences, an empty grid, a bad parameter or value (loso_units), a bad method.
void check_loso(const LosoOptions& o) {
  for (const LosoParameter& p : o.parameters) {
    for (double v : p.grid) {
      if (!std::isfinite(v)) {
        throw Error("loso: grid value " + number_text(v) + " of '" + p.name +
                    "' is not finite (a study file is JSON, which has none: give a large number)");
      }
    }
  }
  loso_units(o);
  const std::vector<int> levels = o.finest_levels.empty() ? std::vector<int>{o.tracker.finest_level} : o.finest_levels;
  for (int level : levels) {
    odometry::TrackerOptions at_level = with_frame_window(o.tracker, o.first_frame, o.max_frames);
    at_level.finest_level = level;
    at_level.backend = "";
    for (const std::vector<double>& setting : loso_settings(o)) {
      odometry::TrackerOptions t = at_level;
      t.method = o.method;
      for (std::size_t k = 0; k < setting.size(); ++k) set_loso_parameter(t, o.parameters[k].name, setting[k]);
      odometry::validate(t);
    }
    std::vector<std::string> fixed = o.methods;
    fixed.push_back(o.reference);
    for (const std::string& m : fixed) {
      odometry::TrackerOptions t = at_level;
      t.method = m;
      odometry::validate(t);
    }
  }
}

}  // namespace

std::vector<std::string> study_sequences(const Study& s) {
  std::vector<std::string> out;
  if (s.table) out.insert(out.end(), s.table->sequences.begin(), s.table->sequences.end());
  if (s.sweep) out.insert(out.end(), s.sweep->sequences.begin(), s.sweep->sequences.end());
  if (s.pareto) {
    for (const auto& p : s.pareto->pairs) out.push_back(p.sequence_dir);
  }
  if (s.loso) out.insert(out.end(), s.loso->sequences.begin(), s.loso->sequences.end());
  return out;
}

std::string method_spec_text(const MethodSpec& spec) {
  return spec.backend.empty() ? spec.method : spec.method + ":" + spec.backend;
}

void check_study(const Study& s) {
  const bool table = s.kind == "table", sweep = s.kind == "sweep", pareto = s.kind == "pareto",
             report = s.kind == "report", loso = s.kind == "loso";
  if (!table && !sweep && !pareto && !report && !loso) {
    throw Error("study: unknown kind '" + s.kind + "' (valid: table, sweep, pareto, report, loso)");
  }
  auto expect = [&](bool present, bool wanted, bool allowed, const char* part) {
    if (wanted && !present) throw Error("study of kind '" + s.kind + "' needs a '" + part + "' part");
    if (present && !wanted && !allowed) throw Error("study of kind '" + s.kind + "' has no '" + part + "' part");
  };
  expect(bool(s.table), table || report, false, "table");
  expect(bool(s.sweep), sweep, report, "sweep");
  expect(bool(s.pareto), pareto, report, "pareto");
  expect(bool(s.report), report, false, "report");
  expect(bool(s.loso), loso, false, "loso");
  odometry::validate(s.tracker);
  if (s.table) check_matrix_options(table_options(s));
  if (s.sweep && (sweep || !s.sweep->sequences.empty())) sweep_units(sweep_options(s));
  if (s.pareto) {
    if (pareto && s.pareto->pairs.empty()) throw Error("study: the pareto part has no pairs");
    ParetoStudyOptions o = s.pareto->options;
    o.tracker = s.tracker;  // as every pair's unit runs (pareto_options): the pairs differ in frames only
    check_pareto_study_options(o);
  }
  if (s.loso) check_loso(loso_options(s));
}

json study_to_json(const Study& s) {
  json j = parts_json(s);
  j["format"] = "bivo-study";
  j["version"] = kFormatVersion;
  j["output"] = s.output;
  j["seed"] = s.seed;
  j["plots"] = s.plots;
  if (s.report) j["report"] = {{"title", s.report->title}, {"preamble", s.report->preamble}};
  j["study_hash"] = study_hash(s);
  return j;
}

Study study_from_json(const json& j, const std::string& where) {
  Reader r(j, where);
  const json* recorded_hash = r.find("study_hash");
  if (r.string("format") != "bivo-study") throw Error(where + ": format must be \"bivo-study\"");
  if (r.integer("version", 0) != kFormatVersion) {
    throw Error(where + ": study format version " + r.need("version").dump() + " (this bivo reads " +
                std::to_string(kFormatVersion) + ")");
  }
  Study s;
  s.kind = r.string("kind");
  s.output = r.string("output");
  const json& seed = r.need("seed");
  if (!seed.is_number_unsigned() && !(seed.is_number_integer() && seed.get<std::int64_t>() >= 0)) {
    throw Error(r.path("seed") + ": must be an integer >= 0, got " + seed.dump());
  }
  s.seed = seed.get<std::uint64_t>();
  s.plots = r.boolean("plots");
  s.tracker = tracker_options_from_json(r.need("tracker"), r.path("tracker"));
  if (const json* t = r.find("table")) {
    Reader tr(*t, r.path("table"));
    MatrixOptions o;
    o.sequences = tr.strings("sequences");
    for (const auto& m : tr.strings("methods")) o.methods.push_back(parse_method_spec(m));
    o.first_frame = tr.integer("first_frame", 0);
    o.max_frames = tr.integer("max_frames", -1);
    tr.number("rpe_delta", o.rpe_delta, 1e-3, 1e6);
    tr.reject_unknown();
    s.table = o;
  }
  if (const json* t = r.find("sweep")) {
    Reader sr(*t, r.path("sweep"));
    SweepOptions o;
    o.sequences = sr.strings("sequences");
    o.lambdas = sr.numbers("lambdas");
    o.epsilons = sr.numbers("epsilons");
    o.epsilon_backend = sr.string("epsilon_backend");
    o.first_frame = sr.integer("first_frame", 0);
    o.max_frames = sr.integer("max_frames", -1);
    sr.number("rpe_delta", o.rpe_delta, 1e-3, 1e6);
    sr.reject_unknown();
    s.sweep = o;
  }
  if (const json* t = r.find("pareto")) {
    Reader pr(*t, r.path("pareto"));
    ParetoPlan p;
    p.options.level = pr.integer("level", 0);
    p.options.points = pr.integer("points", 1);
    p.options.lambda_min = pr.number("lambda_min");
    p.options.lambda_max = pr.number("lambda_max");
    p.options.methods = pr.strings("methods");
    pr.string("backend", p.options.backend);
    int k = 0;
    for (const json& e : pr.array("pairs")) {
      Reader er(e, pr.path("pairs") + "[" + std::to_string(k++) + "]");
      p.pairs.push_back({er.string("sequence"), er.integer("pair", 0)});
      er.reject_unknown();
    }
    pr.reject_unknown();
    s.pareto = p;
  }
  if (const json* t = r.find("loso")) {
    Reader lr(*t, r.path("loso"));
    LosoOptions o;
    o.sequences = lr.strings("sequences");
    o.method = lr.string("method");
    if (const json* several = lr.find("parameters")) {
      if (lr.find("parameter") || lr.find("grid"))
        throw Error(lr.path("parameters") + ": either 'parameters' or 'parameter' and 'grid', not both");
      if (!several->is_array()) throw Error(lr.path("parameters") + ": must be an array, got " + several->type_name());
      o.parameters.clear();
      for (const json& e : *several) {
        Reader er(e, lr.path("parameters") + "[" + std::to_string(o.parameters.size()) + "]");
        o.parameters.push_back({er.string("parameter"), er.numbers("grid")});
        er.reject_unknown();
      }
    } else {
      o.parameters = {{lr.string("parameter"), lr.numbers("grid")}};
    }
    if (const json* levels = lr.find("finest_levels")) {  // absent: the tracker's finest level
      if (!levels->is_array() || levels->empty())
        throw Error(lr.path("finest_levels") + ": must be a non-empty array of levels, got " + levels->dump());
      for (const json& v : *levels) {
        if (!v.is_number_integer() || v.get<std::int64_t>() < 0 || v.get<std::int64_t>() > 7)
          throw Error(lr.path("finest_levels") + ": every entry must be a level in 0..7, got " + v.dump());
        o.finest_levels.push_back(v.get<int>());
      }
    }
    o.reference = lr.string("reference");
    o.methods = lr.strings("methods");
    o.first_frame = lr.integer("first_frame", 0);
    o.max_frames = lr.integer("max_frames", -1);
    lr.number("rpe_delta", o.rpe_delta, 1e-3, 1e6);                                    // absent: 1 s
    lr.number("cost_budget", o.cost_budget, 0.0, std::numeric_limits<double>::max());  // absent: none
    lr.string("cost_method", o.cost_method);
    o.acceptable_ratio = 0.0;  // absent: the smallest worst ratio decides, as planned before the rule
    lr.number("acceptable_ratio", o.acceptable_ratio, 0.0, std::numeric_limits<double>::max());
    lr.reject_unknown();
    s.loso = o;
  }
  if (const json* t = r.find("report")) {
    Reader rr(*t, r.path("report"));
    s.report = ReportText{rr.string("title"), rr.string("preamble")};
    rr.reject_unknown();
  }
  r.reject_unknown();
  try {
    check_study(s);
  } catch (const Error& e) {
    throw Error(where + ": " + e.what());
  }
  // The hash `bivo plan` recorded: an edit by hand (max_frames, a method) would otherwise mix
  // results of two different studies under one name. A file without one cannot be checked.
  if (!recorded_hash) {
    throw Error(where +
                ": the study has no study_hash, so edits since it was planned cannot be detected (written "
                "by an older bivo?); plan it again with `bivo plan`");
  }
  if (!recorded_hash->is_string() || recorded_hash->get<std::string>() != study_hash(s)) {
    throw Error(where + ": the study was changed after it was planned (its hash is " + study_hash(s) + ", recorded " +
                recorded_hash->dump() + "); plan it again with `bivo plan`");
  }
  return s;
}

Study read_study(const std::string& path) {
  return study_from_json(odometry::io::read_json_file(path, "study file"), path);
}

void write_study(const std::string& path, const Study& study) {
  check_study(study);
  const json j = study_to_json(study);
  const std::string text = j.dump(2) + "\n";
  odometry::io::write_file_atomically(path, [&](std::ostream& out) { out << text; });
}

std::string study_hash(const Study& study) {
  json parts = parts_json(study);
  // Threads of the per-pixel passes change no result (where the tracker has them): shards
  // may run with other thread counts than planned and still merge.
  if (parts["tracker"].contains("problem")) parts["tracker"]["problem"].erase("threads");
  parts["tracker"].erase("load_threads");  // nor do the frame loader's
  // A LOSO cost budget only changes which runs' values are chosen, not the runs: finished
  // runs merge under another budget.
  if (parts.contains("loso")) {
    parts["loso"].erase("cost_budget");
    parts["loso"].erase("cost_method");
    parts["loso"].erase("acceptable_ratio");
  }
  const std::string text = parts.dump();      // keys sorted: canonical
  std::uint64_t h = 14695981039346656037ull;  // FNV-1a 64
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

MatrixOptions table_options(const Study& s) {
  MatrixOptions o = s.table.value();
  o.tracker = s.tracker;
  return o;
}

SweepOptions sweep_options(const Study& s) {
  SweepOptions o = s.sweep.value();
  o.tracker = s.tracker;
  return o;
}

ParetoStudyOptions pareto_options(const Study& s, int pair_index) {
  ParetoStudyOptions o = s.pareto.value().options;
  o.tracker = s.tracker;
  o.sequence_dir = s.pareto->pairs.at(pair_index).sequence_dir;
  o.pair = s.pareto->pairs.at(pair_index).pair;
  return o;
}

LosoOptions loso_options(const Study& s) {
  LosoOptions o = s.loso.value();
  o.tracker = s.tracker;
  o.progress = -1;
  return o;
}

std::vector<StudyUnit> study_units(const Study& s) {
  std::vector<StudyUnit> units;
  auto add = [&](const char* part, int item, const std::string& id) {
    units.push_back({int(units.size()), part, item, std::string(part) + "/" + id});
  };
  if (s.table) {
    const auto& t = *s.table;
    for (size_t m = 0; m < t.methods.size(); ++m) {
      for (size_t q = 0; q < t.sequences.size(); ++q) {
        add("table", int(m * t.sequences.size() + q),
            std::to_string(m) + "-" + token(method_spec_text(t.methods[m])) + "/" + std::to_string(q) + "-" +
                token(sequence_label(t.sequences[q])));
      }
    }
  }
  if (s.sweep && !s.sweep->sequences.empty()) {
    const SweepOptions o = sweep_options(s);
    const std::vector<SweepUnit> su = sweep_units(o);
    for (size_t k = 0; k < su.size(); ++k) {
      const auto& u = su[k];
      const int n = u.parameter == "lambda"
                        ? int(std::find(o.lambdas.begin(), o.lambdas.end(), u.value) - o.lambdas.begin())
                        : int(std::find(o.epsilons.begin(), o.epsilons.end(), u.value) - o.epsilons.begin());
      std::string what =
          u.parameter == "single" ? "single" : u.parameter + "-" + std::to_string(n) + "=" + number_text(u.value);
      add("sweep", int(k),
          std::to_string(u.sequence) + "-" + token(sequence_label(o.sequences[u.sequence])) + "/" + token(what));
    }
  }
  if (s.pareto) {
    for (size_t k = 0; k < s.pareto->pairs.size(); ++k) {
      const auto& p = s.pareto->pairs[k];
      add("pareto", int(k),
          std::to_string(k) + "-" + token(sequence_label(p.sequence_dir)) + "/pair-" + std::to_string(p.pair));
    }
  }
  if (s.loso) {
    const LosoOptions o = loso_options(s);
    const std::vector<LosoRun> runs = loso_units(o);
    for (size_t k = 0; k < runs.size(); ++k) {
      const LosoRun& r = runs[k];
      std::string what = token(r.method);
      for (std::size_t p = 0; p < r.values.size(); ++p) {
        const std::vector<double>& grid = o.parameters[p].grid;
        const auto n = std::find(grid.begin(), grid.end(), r.values[p]) - grid.begin();
        what += "/" + token(o.parameters[p].name + "-" + std::to_string(n) + "=" + number_text(r.values[p]));
      }
      if (r.finest_level >= 0) what += "/finest-" + std::to_string(r.finest_level);
      add("loso", int(k),
          std::to_string(r.sequence) + "-" + token(sequence_label(o.sequences[r.sequence])) + "/" + what);
    }
  }
  // Ids must be unique (a grid value listed twice would make two units of one name).
  std::set<std::string> ids;
  for (const auto& u : units) {
    if (!ids.insert(u.id).second) throw Error("study: two units named '" + u.id + "' (a value listed twice?)");
  }
  return units;
}

ShardSpec parse_shard(const std::string& text) {
  // Digits only and bounded: sscanf's %d wrapped 99999999999 to another number.
  constexpr long long kMaxShards = 1000000;
  const auto slash = text.find('/');
  const auto number = [&](const std::string& digits) -> long long {
    if (digits.empty() || digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) return -1;
    return std::stoll(digits);
  };
  const long long index = slash == std::string::npos ? -1 : number(text.substr(0, slash));
  const long long count = slash == std::string::npos ? -1 : number(text.substr(slash + 1));
  if (index < 0 || count < 1 || count > kMaxShards || index >= count) {
    throw Error("--shard '" + text + "': expected I/N with 0 <= I < N <= " + std::to_string(kMaxShards) +
                " (e.g. 0/4)");
  }
  ShardSpec s;
  s.index = int(index);
  s.count = int(count);
  return s;
}

std::vector<StudyUnit> shard_units(const Study& study, const ShardSpec& shard) {
  const std::vector<StudyUnit> units = study_units(study);
  std::vector<int> order(units.size());
  std::iota(order.begin(), order.end(), 0);
  std::uint64_t state = study.seed;
  auto next = [&state] {  // SplitMix64 (Steele, Lea, Flood 2014)
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  };
  for (size_t i = order.size(); i > 1; --i) std::swap(order[i - 1], order[next() % i]);
  std::vector<StudyUnit> mine;
  for (size_t p = shard.index; p < order.size(); p += shard.count) mine.push_back(units[order[p]]);
  std::sort(mine.begin(), mine.end(), [](const StudyUnit& a, const StudyUnit& b) { return a.index < b.index; });
  return mine;
}

}  // namespace bivo::experiments
