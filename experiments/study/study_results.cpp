// Unit results <-> JSON (study_results.h).
#include "experiments/study/study_results.h"

#include <cmath>
#include <limits>

#include <nlohmann/json.hpp>

#include "solvers/error.h"

namespace bivo::experiments {
namespace {

using json = nlohmann::json;

// JSON has no inf/nan (a bounded step's multiplier is +inf when infeasible).
json num(double v) {
  if (std::isfinite(v)) return v;
  return std::isnan(v) ? "nan" : (v > 0 ? "inf" : "-inf");
}
double dbl(const json& j) {
  if (j.is_number()) return j.get<double>();
  if (j.is_string()) {
    const auto s = j.get<std::string>();
    if (s == "inf") return std::numeric_limits<double>::infinity();
    if (s == "-inf") return -std::numeric_limits<double>::infinity();
    if (s == "nan") return std::numeric_limits<double>::quiet_NaN();
  }
  throw Error("expected a number, got " + j.dump());
}

json nums(const std::vector<double>& v) {
  json j = json::array();
  for (double x : v) j.push_back(num(x));
  return j;
}
std::vector<double> dbls(const json& j) {
  std::vector<double> v;
  for (const auto& x : j) v.push_back(dbl(x));
  return v;
}

// A pose as the 12 entries of its upper 3x4 matrix, row-major: exact (a quaternion is not).
json pose(const Eigen::Isometry3d& T) {
  json j = json::array();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) j.push_back(num(T.matrix()(r, c)));
  }
  return j;
}
Eigen::Isometry3d pose_from(const json& j, size_t offset = 0) {
  if (!j.is_array() || j.size() < offset + 12) throw Error("a pose needs 12 numbers, got " + j.dump());
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) T.matrix()(r, c) = dbl(j[offset + 4 * r + c]);
  }
  return T;
}

json trajectory(const odometry::io::Trajectory& t, double from = -INFINITY, double to = INFINITY) {
  json j = json::array();
  for (const auto& p : t) {
    if (p.timestamp < from || p.timestamp > to) continue;
    json row = pose(p.T_wc);
    row.insert(row.begin(), num(p.timestamp));
    j.push_back(row);
  }
  return j;
}
odometry::io::Trajectory trajectory_from(const json& j) {
  odometry::io::Trajectory t;
  for (const auto& row : j) t.push_back({dbl(row.at(0)), pose_from(row, 1)});
  return t;
}

json profile(const solvers::PhaseProfile& p) {
  json j = json::object();
  for (const auto& [name, s] : p.all()) j[name] = num(s);
  return j;
}
solvers::PhaseProfile profile_from(const json& j) {
  solvers::PhaseProfile p;
  for (auto it = j.begin(); it != j.end(); ++it) p.add(it.key(), dbl(it.value()));
  return p;
}

json pose_error(const std::optional<odometry::io::PoseError>& e) {
  if (!e) return nullptr;
  return {num(e->translation_m), num(e->rotation_deg)};
}
std::optional<odometry::io::PoseError> pose_error_from(const json& j) {
  if (j.is_null()) return std::nullopt;
  return odometry::io::PoseError{dbl(j.at(0)), dbl(j.at(1))};
}

json level(const odometry::LevelResult& l) {
  return {{"level", l.level},
          {"terms", l.terms},
          {"valid_intensity", l.valid_intensity},
          {"valid_depth", l.valid_depth},
          {"iterations", l.iterations},
          {"skipped", l.skipped},
          {"f_i", num(l.f_i)},
          {"f_d", num(l.f_d)},
          {"lambda", num(l.lambda)},
          {"epsilon", num(l.epsilon)},
          {"mu", num(l.mu)},
          {"termination", l.termination}};
}
odometry::LevelResult level_from(const json& j) {
  odometry::LevelResult l;
  l.level = j.at("level").get<int>();
  l.terms = j.at("terms").get<int>();
  l.valid_intensity = j.at("valid_intensity").get<int>();
  l.valid_depth = j.at("valid_depth").get<int>();
  l.iterations = j.at("iterations").get<int>();
  l.skipped = j.at("skipped").get<bool>();
  l.f_i = dbl(j.at("f_i"));
  l.f_d = dbl(j.at("f_d"));
  l.lambda = dbl(j.at("lambda"));
  l.epsilon = dbl(j.at("epsilon"));
  l.mu = dbl(j.at("mu"));
  l.termination = j.at("termination").get<std::string>();
  return l;
}

json pair(const odometry::PairResult& p) {
  json levels = json::array();
  for (const auto& l : p.levels) levels.push_back(level(l));
  return {{"index", p.index},
          {"t_reference", num(p.t_reference)},
          {"t_current", num(p.t_current)},
          {"T_21", pose(p.T_21)},
          {"T_wc", pose(p.T_wc)},
          {"valid", p.valid},
          {"note", p.note},
          {"iterations", p.iterations},
          {"lambda", num(p.lambda)},
          {"epsilon", num(p.epsilon)},
          {"mu", num(p.mu)},
          {"epsilon_per_weight", num(p.epsilon_per_weight)},
          {"f_i", num(p.f_i)},
          {"f_d", num(p.f_d)},
          {"seconds", num(p.seconds)},
          {"load_seconds", num(p.load_seconds)},
          {"profile", profile(p.profile)},
          {"levels", levels},
          {"error", pose_error(p.error)}};
}
odometry::PairResult pair_from(const json& j) {
  odometry::PairResult p;
  p.index = j.at("index").get<int>();
  p.t_reference = dbl(j.at("t_reference"));
  p.t_current = dbl(j.at("t_current"));
  p.T_21 = pose_from(j.at("T_21"));
  p.T_wc = pose_from(j.at("T_wc"));
  p.valid = j.at("valid").get<bool>();
  p.note = j.at("note").get<std::string>();
  p.iterations = j.at("iterations").get<int>();
  p.lambda = dbl(j.at("lambda"));
  p.epsilon = dbl(j.at("epsilon"));
  p.mu = dbl(j.at("mu"));
  p.epsilon_per_weight = dbl(j.at("epsilon_per_weight"));
  p.f_i = dbl(j.at("f_i"));
  p.f_d = dbl(j.at("f_d"));
  p.seconds = dbl(j.at("seconds"));
  p.load_seconds = dbl(j.at("load_seconds"));
  p.profile = profile_from(j.at("profile"));
  for (const auto& l : j.at("levels")) p.levels.push_back(level_from(l));
  p.error = pose_error_from(j.at("error"));
  return p;
}

json run(const RunOutcome& r) {
  json pairs = json::array();
  for (const auto& p : r.pairs) pairs.push_back(pair(p));
  json gt = nullptr;
  if (r.groundtruth) {
    const double from = r.trajectory.empty() ? -INFINITY : r.trajectory.front().timestamp - 1.0;
    const double to = r.trajectory.empty() ? INFINITY : r.trajectory.back().timestamp + 1.0;
    gt = trajectory(*r.groundtruth, from, to);
  }
  return {{"sequence", r.sequence},
          {"method", r.method},
          {"backend", r.backend},
          {"trajectory", trajectory(r.trajectory)},
          {"groundtruth", gt},
          {"pairs", pairs},
          {"profile", profile(r.profile)},
          {"failures", r.failures},
          {"median_ms", num(r.median_ms)},
          {"mean_ms", num(r.mean_ms)},
          {"load_seconds", num(r.load_seconds)}};
}
RunOutcome run_from(const json& j) {
  RunOutcome r;
  r.sequence = j.at("sequence").get<std::string>();
  r.method = j.at("method").get<std::string>();
  r.backend = j.at("backend").get<std::string>();
  r.trajectory = trajectory_from(j.at("trajectory"));
  if (!j.at("groundtruth").is_null()) r.groundtruth = trajectory_from(j.at("groundtruth"));
  for (const auto& p : j.at("pairs")) r.pairs.push_back(pair_from(p));
  r.profile = profile_from(j.at("profile"));
  r.failures = j.at("failures").get<int>();
  r.median_ms = dbl(j.at("median_ms"));
  r.mean_ms = dbl(j.at("mean_ms"));
  r.load_seconds = dbl(j.at("load_seconds"));
  return r;
}

json rpe(const odometry::io::RpeResult& r) {
  json windows = json::array();
  for (const auto& w : r.pairs) {
    windows.push_back({num(w.t_est_0), num(w.t_est_1), num(w.t_gt_0), num(w.t_gt_1), num(w.trans), num(w.rot_rad)});
  }
  return {{"windows", windows},
          {"trans_rmse", num(r.trans_rmse)},
          {"trans_mean", num(r.trans_mean)},
          {"trans_median", num(r.trans_median)},
          {"trans_max", num(r.trans_max)},
          {"rot_rmse_deg", num(r.rot_rmse_deg)},
          {"rot_mean_deg", num(r.rot_mean_deg)},
          {"rot_max_deg", num(r.rot_max_deg)}};
}
odometry::io::RpeResult rpe_from(const json& j) {
  odometry::io::RpeResult r;
  for (const auto& w : j.at("windows")) {
    r.pairs.push_back({dbl(w.at(0)), dbl(w.at(1)), dbl(w.at(2)), dbl(w.at(3)), dbl(w.at(4)), dbl(w.at(5))});
  }
  r.trans_rmse = dbl(j.at("trans_rmse"));
  r.trans_mean = dbl(j.at("trans_mean"));
  r.trans_median = dbl(j.at("trans_median"));
  r.trans_max = dbl(j.at("trans_max"));
  r.rot_rmse_deg = dbl(j.at("rot_rmse_deg"));
  r.rot_mean_deg = dbl(j.at("rot_mean_deg"));
  r.rot_max_deg = dbl(j.at("rot_max_deg"));
  return r;
}

json ate(const odometry::io::AteResult& a) {
  return {{"t_est", nums(a.t_est)},         {"t_gt", nums(a.t_gt)}, {"errors", nums(a.errors)},
          {"alignment", pose(a.alignment)}, {"rmse", num(a.rmse)},  {"mean", num(a.mean)},
          {"median", num(a.median)},        {"max", num(a.max)}};
}
odometry::io::AteResult ate_from(const json& j) {
  odometry::io::AteResult a;
  a.t_est = dbls(j.at("t_est"));
  a.t_gt = dbls(j.at("t_gt"));
  a.errors = dbls(j.at("errors"));
  a.alignment = pose_from(j.at("alignment"));
  a.rmse = dbl(j.at("rmse"));
  a.mean = dbl(j.at("mean"));
  a.median = dbl(j.at("median"));
  a.max = dbl(j.at("max"));
  return a;
}

json point(const StudyPoint& p) {
  return {{"f_i", num(p.f_i)},  {"f_d", num(p.f_d)},    {"parameter", num(p.parameter)},
          {"method", p.method}, {"T_21", pose(p.T_21)}, {"error", pose_error(p.error)}};
}
StudyPoint point_from(const json& j) {
  StudyPoint p;
  p.f_i = dbl(j.at("f_i"));
  p.f_d = dbl(j.at("f_d"));
  p.parameter = dbl(j.at("parameter"));
  p.method = j.at("method").get<std::string>();
  p.T_21 = pose_from(j.at("T_21"));
  p.error = pose_error_from(j.at("error"));
  return p;
}
json points(const std::vector<StudyPoint>& v) {
  json j = json::array();
  for (const auto& p : v) j.push_back(point(p));
  return j;
}
std::vector<StudyPoint> points_from(const json& j) {
  std::vector<StudyPoint> v;
  for (const auto& p : j) v.push_back(point_from(p));
  return v;
}

}  // namespace

json matrix_cell_to_json(const MatrixCell& c) {
  return {{"sequence_dir", c.sequence_dir},
          {"sequence", c.sequence},
          {"method", c.spec.method},
          {"requested_backend", c.spec.backend},
          {"backend", c.backend},
          {"note", c.note},
          {"run", c.run ? run(*c.run) : json(nullptr)},
          {"rpe", c.rpe ? rpe(*c.rpe) : json(nullptr)},
          {"ate", c.ate ? ate(*c.ate) : json(nullptr)}};
}

MatrixCell matrix_cell_from_json(const json& j) {
  MatrixCell c;
  c.sequence_dir = j.at("sequence_dir").get<std::string>();
  c.sequence = j.at("sequence").get<std::string>();
  c.spec = {j.at("method").get<std::string>(), j.at("requested_backend").get<std::string>()};
  c.backend = j.at("backend").get<std::string>();
  c.note = j.at("note").get<std::string>();
  if (!j.at("run").is_null()) c.run = run_from(j.at("run"));
  if (!j.at("rpe").is_null()) c.rpe = rpe_from(j.at("rpe"));
  if (!j.at("ate").is_null()) c.ate = ate_from(j.at("ate"));
  return c;
}

json sweep_run_to_json(const SweepRun& r) {
  return {{"sequence_index", r.unit.sequence},
          {"parameter", r.unit.parameter},
          {"value", num(r.unit.value)},
          {"sequence", r.sequence},
          {"ok", r.ok},
          {"rpe_trans", num(r.rpe_trans)},
          {"max_err", num(r.max_err)},
          {"median_ms", num(r.median_ms)},
          {"failures", r.failures},
          {"error", r.error}};
}

SweepRun sweep_run_from_json(const json& j) {
  SweepRun r;
  r.unit = {j.at("sequence_index").get<int>(), j.at("parameter").get<std::string>(), dbl(j.at("value"))};
  r.sequence = j.at("sequence").get<std::string>();
  r.ok = j.at("ok").get<bool>();
  r.rpe_trans = dbl(j.at("rpe_trans"));
  r.max_err = dbl(j.at("max_err"));
  r.median_ms = dbl(j.at("median_ms"));
  r.failures = j.at("failures").get<int>();
  r.error = j.at("error").get<std::string>();
  return r;
}

// One parameter's value as "has_value" and "value", as written before several could be
// chosen together; several as "values" too; a pooled finest level as "finest_level".
json loso_run_to_json(const LosoRun& r) {
  json j = {{"sequence_index", r.sequence},
            {"method", r.method},
            {"has_value", !r.values.empty()},
            {"value", num(r.values.empty() ? 0.0 : r.values[0])},
            {"ok", r.ok},
            {"sequence", r.sequence_name},
            {"error", r.error},
            {"rpe_trans", num(r.rpe_trans)},
            {"rpe_rot", num(r.rpe_rot)},
            {"median_cpu_ms", num(r.median_cpu_ms)},
            {"pair_trans", nums(r.pair_trans)},
            {"pair_rot", nums(r.pair_rot)}};
  if (r.values.size() > 1) j["values"] = nums(r.values);
  if (r.finest_level >= 0) j["finest_level"] = r.finest_level;
  return j;
}

LosoRun loso_run_from_json(const json& j) {
  LosoRun r;
  r.sequence = j.at("sequence_index").get<int>();
  r.method = j.at("method").get<std::string>();
  if (j.contains("values")) {
    r.values = dbls(j.at("values"));
  } else if (j.at("has_value").get<bool>()) {
    r.values = {dbl(j.at("value"))};
  }
  if (j.contains("finest_level")) r.finest_level = j.at("finest_level").get<int>();
  r.ok = j.at("ok").get<bool>();
  r.sequence_name = j.at("sequence").get<std::string>();
  r.error = j.at("error").get<std::string>();
  r.rpe_trans = dbl(j.at("rpe_trans"));
  r.rpe_rot = dbl(j.at("rpe_rot"));
  r.median_cpu_ms = dbl(j.at("median_cpu_ms"));
  r.pair_trans = dbls(j.at("pair_trans"));
  r.pair_rot = dbls(j.at("pair_rot"));
  if (r.pair_trans.size() != r.pair_rot.size()) throw Error("pair_trans and pair_rot differ in length");
  return r;
}

json pareto_outcome_to_json(const ParetoOutcome& o) {
  json study = nullptr;
  if (o.study) {
    const ParetoStudy& s = *o.study;
    study = {{"sequence", s.sequence},
             {"pair", s.pair},
             {"level", s.level},
             {"t_reference", num(s.t_reference)},
             {"t_current", num(s.t_current)},
             {"lambda_front", points(s.lambda_front)},
             {"epsilon_front", points(s.epsilon_front)},
             {"methods", points(s.methods)},
             {"knee", s.knee ? point(*s.knee) : json(nullptr)},
             {"seconds", num(s.seconds)}};
  }
  return {{"study", study}, {"error", o.error}};
}

ParetoOutcome pareto_outcome_from_json(const json& j) {
  ParetoOutcome o;
  o.error = j.at("error").get<std::string>();
  const json& s = j.at("study");
  if (s.is_null()) return o;
  ParetoStudy p;
  p.sequence = s.at("sequence").get<std::string>();
  p.pair = s.at("pair").get<int>();
  p.level = s.at("level").get<int>();
  p.t_reference = dbl(s.at("t_reference"));
  p.t_current = dbl(s.at("t_current"));
  p.lambda_front = points_from(s.at("lambda_front"));
  p.epsilon_front = points_from(s.at("epsilon_front"));
  p.methods = points_from(s.at("methods"));
  if (!s.at("knee").is_null()) p.knee = point_from(s.at("knee"));
  p.seconds = dbl(s.at("seconds"));
  o.study = p;
  return o;
}

}  // namespace bivo::experiments
