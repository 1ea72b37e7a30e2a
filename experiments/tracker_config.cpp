// TrackerOptions <-> JSON (tracker_config.h).
#include "experiments/tracker_config.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <set>
#include <utility>

#include "experiments/json_object_reader.h"
#include "odometry/io/atomic_file.h"
#include "odometry/io/frame_stream.h"
#include "solvers/error.h"

namespace bivo::experiments {

namespace {

using json = nlohmann::json;
using odometry::TrackerOptions;

// The strict reader shared with the study files (json_object_reader.h).
using ObjectReader = JsonObjectReader;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kIntMax = std::numeric_limits<int>::max();

}  // namespace

json tracker_options_to_json(const TrackerOptions& o) {
  const auto& w = o.problem.weights;
  json policy = {{"lambda", o.policy.lambda}, {"phi", o.policy.phi},        {"delta", o.policy.delta},
                 {"eps_min", o.policy.eps_min}, {"eps_max", o.policy.eps_max}, {"eps", nullptr},
                 {"kappa", o.policy.kappa},     {"eps_ratio", o.policy.eps_ratio}, {"guard", o.policy.guard},
                 {"joint_tolerance", o.policy.joint_tolerance}, {"relaxed_tolerance", o.policy.relaxed_tolerance},
                 {"trust", o.policy.trust}};
  if (o.policy.eps) policy["eps"] = *o.policy.eps;
  json j = {
      {"method", o.method},
      {"backend", o.backend},
      {"levels", o.levels},
      {"finest_level", o.finest_level},
      {"initial_guess", odometry::to_string(o.initial_guess)},
      {"max_iterations", o.max_iterations},
      {"step_tolerance", o.step_tolerance},
      {"relative_decrease_tolerance", o.relative_decrease_tolerance},
      {"pixel_motion_tolerance", o.pixel_motion_tolerance},
      {"step_extrapolation", o.step_extrapolation},
      {"exact_finish_iterations", o.exact_finish_iterations},
      {"evaluate_unused_objective", o.evaluate_unused_objective},
      {"min_valid_pixels", o.min_valid_pixels},
      {"max_association_dt", o.max_association_dt},
      {"first_frame", o.first_frame},
      {"max_frames", o.max_frames},
      {"start_at_groundtruth", o.start_at_groundtruth},
      {"prefetch_frames", o.prefetch_frames},
      {"load_threads", o.load_threads},
      {"verbosity", o.verbosity},
      {"policy", policy},
      {"problem",
       {{"min_depth", o.problem.min_depth},
        {"max_depth", o.problem.max_depth},
        {"occlusion_margin", o.problem.occlusion_margin},
        {"depth_first", o.problem.depth_first},
        {"joint_weights", o.problem.joint_weights},
        {"model_f2", o.problem.model_f2},
        {"jacobian", odometry::to_string(o.problem.jacobian)},
        {"threads", o.problem.threads},
        {"weights",
         {{"kind", odometry::to_string(w.kind)},
          {"nu", w.nu},
          {"huber_k", w.huber_k},
          {"max_scale_iterations", w.max_scale_iterations},
          {"scale_tolerance", w.scale_tolerance}}}}},
      {"intrinsics", nullptr},
      {"distortion", nullptr},
  };
  if (o.intrinsics) {
    j["intrinsics"] = {{"fx", o.intrinsics->fx}, {"fy", o.intrinsics->fy}, {"cx", o.intrinsics->cx},
                       {"cy", o.intrinsics->cy}};
  }
  if (o.distortion) {
    j["distortion"] = {{"k1", o.distortion->k1}, {"k2", o.distortion->k2}, {"p1", o.distortion->p1},
                       {"p2", o.distortion->p2}, {"k3", o.distortion->k3}};
  }
  return j;
}

TrackerOptions tracker_options_from_json(const json& j, const std::string& where, const TrackerOptions& base) {
  TrackerOptions o = base;
  ObjectReader r(j, where);
  r.string("method", o.method);
  r.string("backend", o.backend);
  r.integer("levels", o.levels, 1, 12);
  r.integer("finest_level", o.finest_level, 0, 11);
  r.name("initial_guess", o.initial_guess, odometry::parse_initial_guess);
  r.integer("max_iterations", o.max_iterations, 1, 100000);
  r.number("step_tolerance", o.step_tolerance, 0.0, kInf);
  r.number("relative_decrease_tolerance", o.relative_decrease_tolerance, 0.0, kInf);
  r.number("pixel_motion_tolerance", o.pixel_motion_tolerance, 0.0, kInf);
  r.number("step_extrapolation", o.step_extrapolation, 1.0, 100.0);
  r.integer("exact_finish_iterations", o.exact_finish_iterations, 0, 1000);
  r.boolean("evaluate_unused_objective", o.evaluate_unused_objective);
  r.integer("min_valid_pixels", o.min_valid_pixels, 1, kIntMax);
  r.number("max_association_dt", o.max_association_dt, 0.0, 1e6);
  r.integer("first_frame", o.first_frame, 0, kIntMax);
  r.integer("max_frames", o.max_frames, -1, kIntMax);
  r.boolean("start_at_groundtruth", o.start_at_groundtruth);
  r.boolean("prefetch_frames", o.prefetch_frames);
  r.integer("load_threads", o.load_threads, 0, odometry::io::FrameStream::kMaxLoaders);
  r.integer("verbosity", o.verbosity, 0, 10);
  if (const json* p = r.find("policy")) {
    ObjectReader pr(*p, r.path("policy"));
    pr.number("lambda", o.policy.lambda, 0.0, kInf);
    pr.number("phi", o.policy.phi, 0.0, kInf);
    pr.number("delta", o.policy.delta, 0.0, kInf);
    pr.number("eps_min", o.policy.eps_min, 0.0, kInf);
    pr.number("eps_max", o.policy.eps_max, 0.0, kInf);
    pr.number("kappa", o.policy.kappa, 0.0, kInf);
    pr.number("eps_ratio", o.policy.eps_ratio, 0.0, kInf);
    pr.number("guard", o.policy.guard, 0.0, kInf);
    pr.number("joint_tolerance", o.policy.joint_tolerance, 0.0, kInf);
    pr.number("relaxed_tolerance", o.policy.relaxed_tolerance, 0.0, kInf);
    pr.number("trust", o.policy.trust, 0.0, kInf);
    if (const json* e = pr.find("eps")) {
      if (e->is_null()) {
        o.policy.eps.reset();
      } else {
        double eps = 0.0;
        pr.number("eps", eps, 0.0, kInf);
        o.policy.eps = eps;
      }
    }
    pr.reject_unknown();
  }
  if (const json* p = r.find("problem")) {
    ObjectReader pr(*p, r.path("problem"));
    pr.number("min_depth", o.problem.min_depth, 0.0, kInf);
    pr.number("max_depth", o.problem.max_depth, 0.0, kInf);
    pr.number("occlusion_margin", o.problem.occlusion_margin, 0.0, kInf);
    pr.boolean("depth_first", o.problem.depth_first);
    pr.boolean("joint_weights", o.problem.joint_weights);
    pr.boolean("model_f2", o.problem.model_f2);
    pr.name("jacobian", o.problem.jacobian, odometry::parse_jacobian_kind);
    pr.integer("threads", o.problem.threads, 1, 256);
    if (const json* w = pr.find("weights")) {
      auto& wo = o.problem.weights;
      ObjectReader wr(*w, pr.path("weights"));
      wr.name("kind", wo.kind, odometry::parse_weight_kind);
      wr.number("nu", wo.nu, 0.0, kInf);
      wr.number("huber_k", wo.huber_k, 0.0, kInf);
      wr.integer("max_scale_iterations", wo.max_scale_iterations, 1, 100000);
      wr.number("scale_tolerance", wo.scale_tolerance, 0.0, kInf);
      wr.reject_unknown();
    }
    pr.reject_unknown();
  }
  if (const json* k = r.find("intrinsics")) {
    if (k->is_null()) {
      o.intrinsics.reset();
    } else {
      odometry::io::Intrinsics K;
      ObjectReader kr(*k, r.path("intrinsics"));
      kr.number("fx", K.fx, std::numeric_limits<double>::min(), kInf);
      kr.number("fy", K.fy, std::numeric_limits<double>::min(), kInf);
      kr.number("cx", K.cx, -kInf, kInf);
      kr.number("cy", K.cy, -kInf, kInf);
      kr.reject_unknown();
      o.intrinsics = K;
    }
  }
  if (const json* k = r.find("distortion")) {
    if (k->is_null()) {
      o.distortion.reset();
    } else {
      odometry::io::Distortion d;
      ObjectReader dr(*k, r.path("distortion"));
      const std::pair<const char*, double*> fields[] = {
          {"k1", &d.k1}, {"k2", &d.k2}, {"p1", &d.p1}, {"p2", &d.p2}, {"k3", &d.k3}};
      for (const auto& [name, value] : fields) dr.number(name, *value, -kInf, kInf);
      dr.reject_unknown();
      o.distortion = d;
    }
  }
  r.reject_unknown();
  try {
    odometry::validate(o);
  } catch (const Error& e) {
    throw Error(where + ": " + e.what());
  }
  return o;
}

TrackerOptions read_tracker_config(const std::string& path, const TrackerOptions& base) {
  std::ifstream in(path);
  if (!in) throw Error("cannot open tracker configuration '" + path + "'");
  json j;
  try {
    j = json::parse(in);
  } catch (const json::exception& e) {
    throw Error(path + ": not valid JSON (" + e.what() + ")");
  }
  return tracker_options_from_json(j, path, base);
}

void write_tracker_config(const std::string& path, const TrackerOptions& options) {
  const std::string text = tracker_options_to_json(options).dump(2) + "\n";
  odometry::io::write_file_atomically(path, [&](std::ostream& out) { out << text; });
}

}  // namespace bivo::experiments
