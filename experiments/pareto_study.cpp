#include "experiments/pareto_study.h"

#include <chrono>
#include <cstdint>
#include <iomanip>
#include <sstream>

#include <nlohmann/json.hpp>

#include "experiments/plotting.h"
#include "odometry/io/atomic_file.h"
#include "odometry/io/pose_error.h"
#include "odometry/io/tum_dataset.h"
#include "solvers/backend_registry.h"
#include "solvers/error.h"
#include "solvers/geometry/se3.h"

namespace bivo::experiments {
namespace {

// F_I, F_D at T with weights estimated at T (one IRLS weight update, as linearize does).
StudyPoint evaluate(odometry::RgbdOdometryProblem& problem, const Eigen::Isometry3d& T,
                    const std::optional<Eigen::Isometry3d>& truth) {
  const Eigen::VectorXd x = solvers::se3::to_ambient(T);
  solvers::LinearizeOptions lo;
  problem.linearize(x, lo);
  StudyPoint p;
  p.f_i = problem.last_stats().f_intensity;
  p.f_d = problem.last_stats().f_depth;
  p.T_21 = T;
  if (truth) p.error = odometry::io::pose_error(T, *truth);
  return p;
}

std::vector<StudyPoint> front_points(const solvers::ParetoFront& front, odometry::RgbdOdometryProblem& problem,
                                     const std::optional<Eigen::Isometry3d>& truth) {
  std::vector<solvers::ParetoPoint> evaluated;
  std::vector<StudyPoint> pts;
  for (const auto& p : front.all) {
    if (!p.x.allFinite()) continue;
    StudyPoint s = evaluate(problem, solvers::se3::from_ambient(p.x), truth);
    s.parameter = p.parameter;
    pts.push_back(s);
  }
  // Keep what is still non-dominated after the common re-evaluation.
  std::vector<StudyPoint> out;
  for (const auto& a : pts) {
    bool dominated = false;
    for (const auto& b : pts) {
      if (b.f_i <= a.f_i && b.f_d <= a.f_d && (b.f_i < a.f_i || b.f_d < a.f_d)) dominated = true;
    }
    if (!dominated) out.push_back(a);
  }
  std::sort(out.begin(), out.end(), [](const StudyPoint& a, const StudyPoint& b) { return a.f_i < b.f_i; });
  return out;
}

// single at the study's level: the tracker of the pair's start and of its problem.
odometry::TrackerOptions pareto_tracker(const ParetoStudyOptions& o) {
  odometry::TrackerOptions base = o.tracker;
  base.method = "single";
  base.backend = "";
  base.finest_level = o.level;
  return base;
}

}  // namespace

void check_pareto_study_options(const ParetoStudyOptions& o) {
  if (o.points < 2 || o.points > 1000) {
    throw Error("pareto: points per sweep must be in 2..1000, got " + std::to_string(o.points));
  }
  if (!o.backend.empty()) solvers::backend_info(o.backend);  // throws listing the valid names
  solvers::check_lambda_range(o.lambda_min, o.lambda_max);
  // The fronts are swept on one problem of the frames as given: a method estimated on retimed
  // depth or global-shutter colour would be scored on other data than it used.
  if (o.tracker.retime_depth != 0) {
    throw Error("pareto: --retime-depth " + std::to_string(o.tracker.retime_depth) +
                ": the fronts use the depth images as taken; sweep without it");
  }
  if (o.tracker.readout_time > 0.0) {  // -1, the sequence's: the fronts use the images as taken
    std::ostringstream value;
    value << o.tracker.readout_time;
    throw Error("pareto: --readout-time " + value.str() +
                ": the fronts use the colour images as taken; sweep without it");
  }
  // The level and the marked methods as the tracker takes them.
  const odometry::TrackerOptions base = pareto_tracker(o);
  odometry::validate(base);
  for (const auto& m : o.methods) {
    odometry::TrackerOptions t = base;
    t.method = m;
    odometry::validate(t);
  }
}

ParetoStudy run_pareto_study(const ParetoStudyOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  check_pareto_study_options(o);
  const odometry::TrackerOptions base = pareto_tracker(o);
  const odometry::FramePair pair = odometry::load_frame_pair(o.sequence_dir, o.pair, o.pair + 1, base);
  ParetoStudy study;
  study.sequence = pair.sequence;
  study.pair = o.pair;
  study.level = o.level;
  study.t_reference = pair.reference_frame.rgb_time;
  study.t_current = pair.current_frame.rgb_time;

  // Start both sweeps from the single-objective coarse-to-fine estimate down to this level,
  // the same basin the methods start in.
  const odometry::PairResult start =
      odometry::estimate_motion(pair.reference, pair.current, Eigen::Isometry3d::Identity(), pair.as_loaded(base));
  const Eigen::VectorXd x0 = solvers::se3::to_ambient(start.T_21);
  auto problem = pair.problem(o.level, base);  // F_1 = F_I, F_2 = F_D

  solvers::ParetoOptions po;
  po.points = o.points;
  po.lambda_min = o.lambda_min;
  po.lambda_max = o.lambda_max;
  po.solver.max_iterations = base.max_iterations;
  po.solver.step_tolerance = base.step_tolerance;
  po.solver.relative_decrease_tolerance = base.relative_decrease_tolerance;
  po.solver.max_step_extrapolation =
      odometry::method_step_extrapolation(odometry::parse_method(base.method), base.step_extrapolation);
  if (base.pixel_motion_tolerance > 0.0) {
    // Warm-started neighbours often differ by less than anyone can see: stop there.
    odometry::RgbdOdometryProblem* p = problem.get();
    po.solver.step_measure = [p](const Eigen::VectorXd& x, const Eigen::VectorXd& d) { return p->pixel_motion(x, d); };
    po.solver.step_measure_tolerance = base.pixel_motion_tolerance;
  }
  solvers::ParetoOptions lambda_po = po, epsilon_po = po;
  if (!o.backend.empty()) {
    const solvers::BackendInfo& info = solvers::backend_info(o.backend);
    if (info.weighted_sum) lambda_po.backend = o.backend;
    if (info.epsilon_constraint) epsilon_po.backend = o.backend;
  }
  const solvers::ParetoFront lf = solvers::sweep_lambda(*problem, x0, lambda_po);
  const solvers::ParetoFront ef = solvers::sweep_epsilon(*problem, x0, epsilon_po);
  study.lambda_front = front_points(lf, *problem, pair.groundtruth_T21);
  study.epsilon_front = front_points(ef, *problem, pair.groundtruth_T21);

  for (const auto& m : o.methods) {
    odometry::TrackerOptions t = base;
    t.method = m;
    const odometry::PairResult r =
        odometry::estimate_motion(pair.reference, pair.current, Eigen::Isometry3d::Identity(), pair.as_loaded(t));
    StudyPoint p = evaluate(*problem, r.T_21, pair.groundtruth_T21);
    p.method = m;
    p.parameter = m == "bounded" ? r.epsilon_per_weight : r.lambda;
    study.methods.push_back(p);
  }

  std::vector<solvers::ParetoPoint> both;
  std::vector<const StudyPoint*> refs;
  for (const auto* f : {&study.lambda_front, &study.epsilon_front}) {
    for (const auto& p : *f) {
      solvers::ParetoPoint q;
      q.f1 = p.f_i;
      q.f2 = p.f_d;
      q.x = solvers::se3::to_ambient(p.T_21);
      both.push_back(q);
      refs.push_back(&p);
    }
  }
  const auto front = solvers::nondominated(both);
  if (const auto k = solvers::knee_index(front)) {
    for (size_t i = 0; i < both.size(); ++i) {
      if (both[i].f1 == front[*k].f1 && both[i].f2 == front[*k].f2) {
        study.knee = *refs[i];
        break;
      }
    }
  }
  study.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return study;
}

std::string pareto_json(const ParetoStudy& s) {
  auto point = [](const StudyPoint& p, const char* parameter) {
    nlohmann::json j = {{"f_i", p.f_i}, {"f_d", p.f_d}};
    if (parameter) j[parameter] = p.parameter;
    if (!p.method.empty()) j["method"] = p.method;
    if (p.error) {
      j["trans_err_m"] = p.error->translation_m;
      j["rot_err_deg"] = p.error->rotation_deg;
    }
    return j;
  };
  nlohmann::json j;
  std::ostringstream title;
  title << s.sequence << " pair " << s.pair << " (level " << s.level << ")";
  j["title"] = title.str();
  j["sequence"] = s.sequence;
  j["pair"] = s.pair;
  j["level"] = s.level;
  j["t_reference"] = s.t_reference;
  j["t_current"] = s.t_current;
  j["lambda_sweep"] = nlohmann::json::array();
  for (const auto& p : s.lambda_front) j["lambda_sweep"].push_back(point(p, "lambda"));
  j["epsilon_sweep"] = nlohmann::json::array();
  for (const auto& p : s.epsilon_front) j["epsilon_sweep"].push_back(point(p, "epsilon"));
  j["methods"] = nlohmann::json::array();
  for (const auto& p : s.methods) j["methods"].push_back(point(p, "parameter"));
  j["knee"] = s.knee ? point(*s.knee, nullptr) : nlohmann::json(nullptr);
  j["seconds"] = s.seconds;
  return j.dump(2) + "\n";
}

std::vector<int> pareto_pairs(const std::string& sequence_dir, int pair, int every, int max_pairs) {
  if (pair < 0 && every <= 0) throw Error("give --pair K (K >= 0) or --every K (K >= 1)");
  if (pair < 0 && max_pairs < 1) throw Error("--max-pairs must be >= 1, got " + std::to_string(max_pairs));
  // Every pair is checked against the sequence before any study runs (in 64 bits: k + every
  // and pair + 1 may exceed INT_MAX).
  const std::int64_t frames = static_cast<std::int64_t>(odometry::io::open_tum_sequence(sequence_dir).frames.size());
  std::vector<int> pairs;
  if (pair >= 0) {
    if (std::int64_t{pair} + 1 >= frames) {
      throw Error("--pair " + std::to_string(pair) + ": sequence '" + sequence_dir + "' has " + std::to_string(frames) +
                  " frames, pairs 0.." + std::to_string(frames - 2));
    }
    pairs.push_back(pair);
  } else {
    for (std::int64_t k = 0; k + 1 < frames && std::int64_t(pairs.size()) < max_pairs; k += every) {
      pairs.push_back(static_cast<int>(k));
    }
  }
  return pairs;
}

std::string write_pareto_studies(const std::vector<ParetoStudy>& studies, const std::vector<std::string>& methods,
                                 const std::string& dir, bool plots) {
  odometry::io::create_output_directory(dir);
  std::ostringstream md;
  md << "| pair | level | lambda-front points | epsilon-front points | knee F_I | knee F_D | knee error [mm] |";
  for (const auto& m : methods) md << " " << m << " error [mm] |";
  md << " seconds |\n|---|---:|---:|---:|---:|---:|---:|";
  for (size_t i = 0; i < methods.size(); ++i) md << "---:|";
  md << "---:|\n";
  auto mm = [](const StudyPoint& p) {
    std::ostringstream s;
    if (p.error)
      s << std::fixed << std::setprecision(2) << 1000.0 * p.error->translation_m;
    else
      s << "—";
    return s.str();
  };
  odometry::io::StagedOutputs out;
  for (const ParetoStudy& s : studies) {
    const int k = s.pair;
    out.add(dir + "/pareto_pair" + std::to_string(k) + ".json", [&](std::ostream& o) { o << pareto_json(s); });
    md << "| " << k << " | " << s.level << " | " << s.lambda_front.size() << " | " << s.epsilon_front.size() << " | ";
    if (s.knee)
      md << std::setprecision(6) << s.knee->f_i << " | " << s.knee->f_d << " | " << mm(*s.knee) << " |";
    else
      md << "— | — | — |";
    for (const auto& p : s.methods) md << " " << mm(p) << " |";
    md << " " << std::fixed << std::setprecision(1) << s.seconds << std::defaultfloat << " |\n";
  }
  out.add(dir + "/pareto.md", [&](std::ostream& o) { o << md.str(); });
  out.commit();
  if (plots) {
    for (const ParetoStudy& s : studies) {
      const std::string base = dir + "/pareto_pair" + std::to_string(s.pair);
      plot("pareto_front.py", {base + ".json", base + ".png"});
    }
  }
  return md.str();
}

}  // namespace bivo::experiments
