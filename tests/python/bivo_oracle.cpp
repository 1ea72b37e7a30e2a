// The C++ side of the Python tests (tests/python): runs a computation through the C++ API
// directly and prints the numbers as JSON (doubles round-trip exactly), so the bindings are
// checked against what C++ gives for the same call, to 1e-12. Usage:
//   bivo_oracle solve PROBLEM BACKEND ws|eps PARAM      PROBLEM: lls:N:SEED | exp:M:SEED | se3:SEED
//   bivo_oracle pareto PROBLEM epsilon|lambda POINTS BACKEND
//   bivo_oracle conic FILE.json
//   bivo_oracle pair SEQUENCE REF CUR LEVEL METHOD BACKEND
//   bivo_oracle track SEQUENCE METHOD BACKEND MAX_FRAMES
//   bivo_oracle metrics GROUNDTRUTH ESTIMATE DELTA_S
#include <cmath>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "experiments/conic_files/conic_file.h"
#include "experiments/trajectory_evaluation.h"
#include "odometry/tracker.h"
#include "problems/exponential_decay_pair.h"
#include "problems/linear_least_squares_pair.h"
#include "problems/point_alignment_pair.h"
#include "solvers/backend_registry.h"
#include "solvers/error.h"
#include "solvers/geometry/se3.h"
#include "solvers/outer_loop.h"
#include "solvers/pareto.h"

namespace {

using namespace bivo;
using nlohmann::json;

// JSON has no infinity or NaN: those are written as the strings "inf", "-inf", "nan".
json num(double v) {
  if (std::isfinite(v)) return v;
  return std::isnan(v) ? "nan" : (v > 0 ? "inf" : "-inf");
}
json vec(const Eigen::VectorXd& v) {
  json a = json::array();
  for (double x : v) a.push_back(num(x));
  return a;
}

// The test problems and the start points the Python tests use for them.
struct Instance {
  std::unique_ptr<solvers::BiObjectiveProblem> problem;
  Eigen::VectorXd x0;
};

Instance instance(const std::string& spec) {
  const auto a = spec.find(':');
  const std::string kind = spec.substr(0, a);
  std::vector<int> n;
  for (std::size_t p = a; p != std::string::npos;) {
    const auto q = spec.find(':', p + 1);
    n.push_back(std::stoi(spec.substr(p + 1, q == std::string::npos ? q : q - p - 1)));
    p = q;
  }
  Instance in;
  if (kind == "lls") {
    in.problem = std::make_unique<problems::LinearLeastSquaresPair>(
        problems::LinearLeastSquaresPair::well_conditioned(n.at(0), n.at(1)));
    in.x0 = Eigen::VectorXd::Zero(n.at(0));
  } else if (kind == "exp") {
    in.problem =
        std::make_unique<problems::ExponentialDecayPair>(problems::ExponentialDecayPair::synthetic(n.at(0), n.at(1)));
    in.x0 = Eigen::Vector3d(1.0, 1.0, 1.0);
  } else if (kind == "se3") {
    in.problem = std::make_unique<problems::PointAlignmentPair>(n.at(0));
    in.x0 = Eigen::VectorXd::Zero(7);
    in.x0(6) = 1.0;
  } else {
    throw Error("unknown problem '" + spec + "'");
  }
  return in;
}

json summary_json(const solvers::Summary& s, const Eigen::VectorXd& x) {
  json j;
  j["x"] = vec(x);
  j["iterations"] = s.iterations;
  j["final_f1"] = num(s.final_f1);
  j["final_f2"] = num(s.final_f2);
  j["multiplier"] = num(s.multiplier);
  j["termination"] = solvers::to_string(s.termination);
  for (const auto& r : s.records) {
    j["f1"].push_back(num(r.f1));
    j["f2"].push_back(num(r.f2));
    j["multipliers"].push_back(num(r.multiplier));
    j["iterates"].push_back(vec(r.x));
  }
  return j;
}

json solve(const std::string& spec, const std::string& backend, const std::string& kind, double param) {
  Instance in = instance(spec);
  std::unique_ptr<solvers::Scalarization> s;
  if (kind == "ws")
    s = std::make_unique<solvers::WeightedSum>(param);
  else
    s = std::make_unique<solvers::EpsilonConstraint>(param);
  Eigen::VectorXd x = in.x0;
  return summary_json(solvers::solve(*in.problem, *s, backend, x, {}), x);
}

json pareto(const std::string& spec, const std::string& kind, int points, const std::string& backend) {
  Instance in = instance(spec);
  solvers::ParetoOptions o;
  o.points = points;
  o.backend = backend;
  const solvers::ParetoFront f =
      kind == "epsilon" ? solvers::sweep_epsilon(*in.problem, in.x0, o) : solvers::sweep_lambda(*in.problem, in.x0, o);
  json j;
  double r1 = 0.0, r2 = 0.0;
  for (const auto& p : f.points) {
    j["f1"].push_back(p.f1);
    j["f2"].push_back(p.f2);
    j["parameters"].push_back(num(p.parameter));
    r1 = std::max(r1, p.f1), r2 = std::max(r2, p.f2);
  }
  const auto k = solvers::knee_index(f.points);
  j["knee"] = k ? json(*k) : json(nullptr);
  j["hypervolume"] = solvers::hypervolume(f.points, r1, r2);
  return j;
}

json conic(const std::string& path) {
  const auto r = solvers::conic::solve_conic(experiments::read_conic_json(path));
  return {{"x", vec(r.x)},
          {"y", vec(r.y)},
          {"z", vec(r.z)},
          {"s", vec(r.s)},
          {"status", solvers::conic::to_string(r.status)},
          {"iterations", r.iterations},
          {"primal_objective", r.primal_objective}};
}

json pair(const std::string& seq, int ref, int cur, int level, const std::string& method, const std::string& backend) {
  odometry::TrackerOptions o;
  o.method = method;
  o.backend = backend;
  const odometry::FramePair p = odometry::load_frame_pair(seq, ref, cur, o);
  auto problem = p.problem(level, o);
  Eigen::VectorXd x0 = Eigen::VectorXd::Zero(7);
  x0(6) = 1.0;
  json j;
  j["objectives_at_identity"] = problem->objectives_at(x0);
  const solvers::WeightedSum ws(p.lambda(o));
  Eigen::VectorXd x = x0;
  j["solve"] = summary_json(solvers::solve(*problem, ws, "gn", x, {}), x);
  const odometry::PairResult r = odometry::estimate_motion(p.reference, p.current, Eigen::Isometry3d::Identity(), o);
  j["T_21"] = vec(solvers::se3::to_ambient(r.T_21));
  j["lambda"] = p.lambda(o);
  return j;
}

json track(const std::string& seq, const std::string& method, const std::string& backend, int max_frames) {
  odometry::TrackerOptions o;
  o.method = method;
  o.backend = backend;
  o.max_frames = max_frames;
  const odometry::TrackResult r = odometry::track_sequence(seq, o);
  json j;
  for (const auto& pose : r.trajectory) j["poses"].push_back(vec(solvers::se3::to_ambient(pose.T_wc)));
  for (const auto& p : r.pairs) {
    j["iterations"].push_back(p.iterations);
    json levels = json::array();
    for (const auto& l : p.levels) {
      levels.push_back({{"valid_intensity", l.valid_intensity},
                        {"valid_depth", l.valid_depth},
                        {"iterations", l.iterations},
                        {"skipped", l.skipped},
                        {"lam", num(l.lambda)},
                        {"correlation", num(l.correlation)},
                        {"relaxed", l.relaxed},
                        {"kept_prior", l.kept_prior},
                        {"trust", num(l.trust)},
                        {"guard_rise", num(l.guard_rise)}});
    }
    j["pairs"].push_back({{"correlation", num(p.correlation)},
                          {"relaxed_levels", p.relaxed_levels},
                          {"trust", num(p.trust)},
                          {"epsilon_per_weight", num(p.epsilon_per_weight)},
                          {"levels", levels}});
  }
  return j;
}

json metrics(const std::string& gt, const std::string& est, double delta) {
  const auto e = experiments::evaluate_trajectory_files(gt, est, delta);
  return {{"rpe_trans_rmse", e.rpe.trans_rmse},
          {"rpe_rot_rmse_deg", e.rpe.rot_rmse_deg},
          {"ate_rmse", e.ate.rmse},
          {"rpe_pairs", e.rpe.pairs.size()}};
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::vector<std::string> a(argv + 1, argv + argc);
    json out;
    if (a.size() == 5 && a[0] == "solve")
      out = solve(a[1], a[2], a[3], std::stod(a[4]));
    else if (a.size() == 5 && a[0] == "pareto")
      out = pareto(a[1], a[2], std::stoi(a[3]), a[4]);
    else if (a.size() == 2 && a[0] == "conic")
      out = conic(a[1]);
    else if (a.size() == 7 && a[0] == "pair")
      out = pair(a[1], std::stoi(a[2]), std::stoi(a[3]), std::stoi(a[4]), a[5], a[6]);
    else if (a.size() == 5 && a[0] == "track")
      out = track(a[1], a[2], a[3], std::stoi(a[4]));
    else if (a.size() == 4 && a[0] == "metrics")
      out = metrics(a[1], a[2], std::stod(a[3]));
    else
      throw bivo::Error("usage: see the header of tests/python/bivo_oracle.cpp");
    std::cout << out.dump() << "\n";
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "bivo_oracle: " << e.what() << "\n";
    return 1;
  }
}
