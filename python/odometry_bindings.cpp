// The odometry instance in Python (submodule bivo.odometry, plus bivo.track): tracker
// options as keyword arguments (the keys of `bivo run --config`, experiments/tracker_config.h),
// one frame pair and its per-level problem, one pair's estimate, a whole sequence, and the
// synthetic renderer. Poses are 7-vectors [tx ty tz qx qy qz qw] (the SE(3) problems' x).
#include <cmath>
#include <limits>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <nlohmann/json.hpp>

#include "experiments/tracker_config.h"
#include "experiments/tracker_option_table.h"
#include "odometry/io/trajectory.h"
#include "odometry/io/tum_dataset.h"
#include "odometry/synth/sequence.h"
#include "odometry/tracker.h"
#include "python/bindings.h"
#include "solvers/geometry/se3.h"

namespace bivo::python {
namespace {

using namespace odometry;
using solvers::se3::to_ambient;

// Keyword arguments -> TrackerOptions through the tracker option table: a keyword is a
// top-level key of the configuration (levels=3, policy={"phi": 50}) or an option's flat
// Python name (phi=50, nu=3); both are checked by the code that checks files and flags, so
// unknown keys and out-of-range values are bivo.Error naming the key
// ("tracker options: problem.weights.nu: -2 is outside (0, inf]").
TrackerOptions options_of(const py::kwargs& kwargs) {
  const std::string text = py::module_::import("json").attr("dumps")(kwargs).cast<std::string>();
  const nlohmann::json given = nlohmann::json::parse(text);
  nlohmann::json config = nlohmann::json::object();
  nlohmann::json flat = nlohmann::json::object();
  const nlohmann::json top = experiments::tracker_options_to_json({});
  for (auto it = given.begin(); it != given.end(); ++it) {
    const bool top_level = top.contains(it.key());
    const experiments::TrackerOption* option = experiments::find_tracker_option_by_python_name(it.key());
    if (top_level || !option) {
      config[it.key()] = it.value();
    } else {
      flat[option->key] = it.value();
    }
  }
  TrackerOptions o = experiments::tracker_options_from_json(config, "tracker options");
  for (auto it = flat.begin(); it != flat.end(); ++it) {
    try {
      experiments::apply_tracker_option(*experiments::find_tracker_option_by_key(it.key()), it.value(), o);
    } catch (const Error& e) {
      throw Error(std::string("tracker options: ") + e.what());
    }
  }
  try {
    validate(o);
  } catch (const Error& e) {
    throw Error(std::string("tracker options: ") + e.what());
  }
  return o;
}

// The table as Python sees it: one dict per option.
py::list option_table() {
  py::list rows;
  const TrackerOptions defaults;
  for (const auto& o : experiments::tracker_option_table()) {
    const std::string d = o.get(defaults).dump();
    rows.append(py::dict(py::arg("key") = o.key, py::arg("python_name") = o.python_name(), py::arg("flag") = o.flag,
                         py::arg("range") = o.range_text(), py::arg("method") = o.method, py::arg("help") = o.help,
                         py::arg("default") = py::module_::import("json").attr("loads")(d)));
  }
  return rows;
}

struct PyFramePair {
  PyFramePair() = default;
  PyFramePair(PyFramePair&&) = default;
  PyFramePair(const PyFramePair&) = delete;  // pyramids are move-only
  FramePair pair;
  TrackerOptions options;
};

py::object pose_or_none(const std::optional<Eigen::Isometry3d>& T) {
  if (!T) return py::none();
  return py::cast(Eigen::VectorXd(to_ambient(*T)));
}

Eigen::MatrixXd poses(const io::Trajectory& t) {
  Eigen::MatrixXd P(t.size(), 7);
  for (std::size_t i = 0; i < t.size(); ++i) P.row(static_cast<Eigen::Index>(i)) = to_ambient(t[i].T_wc).transpose();
  return P;
}

template <class F>
Eigen::VectorXd pair_column(const std::vector<PairResult>& pairs, F field) {
  Eigen::VectorXd v(pairs.size());
  for (std::size_t i = 0; i < pairs.size(); ++i) v(static_cast<Eigen::Index>(i)) = field(pairs[i]);
  return v;
}

double nan_if_absent(const std::optional<io::PoseError>& e, double io::PoseError::*field) {
  return e ? (*e).*field : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

void bind_odometry(py::module_& m) {
  auto om = m.def_submodule("odometry", "RGB-D odometry: frame pairs, per-pair problems, tracking, synthetic data.");

  om.def("methods", &method_names, "The odometry methods (odometry/odometry_methods.h).");
  om.def(
      "tracker_options",
      [](const py::kwargs& kwargs) {
        const std::string text = experiments::tracker_options_to_json(options_of(kwargs)).dump();
        return py::module_::import("json").attr("loads")(text);
      },
      "The complete tracker configuration (a dict) that these keyword arguments give.");
  om.def("tracker_option_table", &option_table,
         "Every tracker option: JSON key, Python keyword, flag of `bivo run`, valid range, method, help, default.");

  py::class_<LevelResult>(om, "LevelResult")
      .def_readonly("level", &LevelResult::level)
      .def_readonly("terms", &LevelResult::terms)
      .def_readonly("valid_intensity", &LevelResult::valid_intensity)
      .def_readonly("valid_depth", &LevelResult::valid_depth)
      .def_readonly("iterations", &LevelResult::iterations)
      .def_readonly("skipped", &LevelResult::skipped)
      .def_readonly("f_i", &LevelResult::f_i)
      .def_readonly("f_d", &LevelResult::f_d)
      .def_readonly("lam", &LevelResult::lambda)
      .def_readonly("correlation", &LevelResult::correlation)
      .def_readonly("relaxed", &LevelResult::relaxed)
      .def_readonly("kept_prior", &LevelResult::kept_prior)
      .def_readonly("trust", &LevelResult::trust)
      .def_readonly("guard_rise", &LevelResult::guard_rise)
      .def_readonly("epsilon", &LevelResult::epsilon)
      .def_readonly("mu", &LevelResult::mu)
      .def_readonly("termination", &LevelResult::termination);

  py::class_<PairResult>(om, "PairResult", "One pair's estimate (odometry/tracker.h); poses as 7-vectors.")
      .def_readonly("index", &PairResult::index)
      .def_readonly("t_reference", &PairResult::t_reference)
      .def_readonly("t_current", &PairResult::t_current)
      .def_property_readonly("T_21", [](const PairResult& p) { return Eigen::VectorXd(to_ambient(p.T_21)); })
      .def_property_readonly("T_wc", [](const PairResult& p) { return Eigen::VectorXd(to_ambient(p.T_wc)); })
      .def_readonly("valid", &PairResult::valid)
      .def_readonly("note", &PairResult::note)
      .def_readonly("iterations", &PairResult::iterations)
      .def_readonly("lam", &PairResult::lambda)
      .def_readonly("epsilon", &PairResult::epsilon)
      .def_readonly("mu", &PairResult::mu)
      .def_readonly("correlation", &PairResult::correlation)
      .def_readonly("relaxed_levels", &PairResult::relaxed_levels)
      .def_readonly("trust", &PairResult::trust)
      .def_readonly("epsilon_per_weight", &PairResult::epsilon_per_weight)
      .def_readonly("f_i", &PairResult::f_i)
      .def_readonly("f_d", &PairResult::f_d)
      .def_readonly("seconds", &PairResult::seconds)
      .def_readonly("cpu_seconds", &PairResult::cpu_seconds)
      .def_readonly("load_seconds", &PairResult::load_seconds)
      .def_readonly("levels", &PairResult::levels)
      .def_property_readonly("translation_error",
                             [](const PairResult& p) { return nan_if_absent(p.error, &io::PoseError::translation_m); })
      .def_property_readonly("rotation_error_deg",
                             [](const PairResult& p) { return nan_if_absent(p.error, &io::PoseError::rotation_deg); })
      .def_property_readonly("phases", [](const PairResult& p) { return p.profile.all(); });

  py::class_<RgbdOdometryProblem, solvers::BiObjectiveProblem>(
      om, "RgbdOdometryProblem",
      "One frame pair at one pyramid level: F1 = F_I, F2 = F_D over x = T_21 (odometry/rgbd_problem.h).")
      .def_property_readonly("num_terms", &RgbdOdometryProblem::num_terms)
      .def(
          "objectives_at",
          [](RgbdOdometryProblem& p, const py::object& x) { return p.objectives_at(vector_arg(x, "x", 7)); },
          py::arg("x"), "(F_I, F_D) at x with both weightings estimated at x");

  py::class_<PyFramePair>(om, "FramePair", "Two frames of a TUM sequence, preprocessed (odometry/tracker.h).")
      .def_property_readonly("sequence", [](const PyFramePair& p) { return p.pair.sequence; })
      .def_property_readonly("t_reference", [](const PyFramePair& p) { return p.pair.reference_frame.rgb_time; })
      .def_property_readonly("t_current", [](const PyFramePair& p) { return p.pair.current_frame.rgb_time; })
      .def_property_readonly("levels", [](const PyFramePair& p) { return p.pair.reference.pyramid.levels.size(); })
      .def_property_readonly(
          "groundtruth_T21", [](const PyFramePair& p) { return pose_or_none(p.pair.groundtruth_T21); },
          "true motion as a 7-vector, None without ground truth")
      .def(
          "problem", [](const PyFramePair& p, int level) { return p.pair.problem(level, p.options); },
          py::arg("level") = 0, py::keep_alive<0, 1>(),
          "The odometry problem at a pyramid level with this pair's options (it refers into the pair).")
      .def(
          "lam", [](const PyFramePair& p) { return p.pair.lambda(p.options); },
          "lambda the options' weighted-sum method would use on this pair")
      .def("epsilon_per_weight", [](const PyFramePair& p) { return p.pair.epsilon_per_weight(p.options); })
      .def(
          "estimate",
          [](const PyFramePair& p, const py::object& initial, const py::kwargs& kwargs) {
            const TrackerOptions o = p.pair.as_loaded(
                with_stated_sensor(kwargs.empty() ? p.options : options_of(kwargs), p.pair.readout_time, std::nullopt));
            const Eigen::Isometry3d T0 = initial.is_none()
                                             ? Eigen::Isometry3d::Identity()
                                             : solvers::se3::from_ambient(vector_arg(initial, "initial", 7));
            py::gil_scoped_release release;
            PairResult r = estimate_motion(p.pair.reference, p.pair.current, T0, o);
            if (p.pair.groundtruth_T21) r.error = io::pose_error(r.T_21, *p.pair.groundtruth_T21);
            return r;
          },
          py::arg("initial") = py::none(),
          "Coarse-to-fine estimate of T_21 from `initial` (identity); keyword arguments replace the pair's options.");

  om.def(
      "open_sequence",
      [](const std::string& path, double max_association_dt) {
        io::SequenceOptions so;
        so.max_association_dt = max_association_dt;
        const io::TumSequence seq = io::open_tum_sequence(path, so);
        py::dict d;
        d["name"] = seq.name;
        d["directory"] = seq.directory;
        d["readout_time"] = seq.readout_time ? py::object(py::float_(*seq.readout_time)) : py::none();
        d["vignetting"] = seq.vignetting ? py::object(py::float_(*seq.vignetting)) : py::none();
        d["intrinsics"] = py::dict(py::arg("fx") = seq.intrinsics.fx, py::arg("fy") = seq.intrinsics.fy,
                                   py::arg("cx") = seq.intrinsics.cx, py::arg("cy") = seq.intrinsics.cy);
        const io::Distortion& dist = seq.distortion;
        d["distortion"] = py::dict(py::arg("k1") = dist.k1, py::arg("k2") = dist.k2, py::arg("p1") = dist.p1,
                                   py::arg("p2") = dist.p2, py::arg("k3") = dist.k3);
        Eigen::VectorXd t(seq.frames.size());
        py::list rgb, depth;
        for (std::size_t i = 0; i < seq.frames.size(); ++i) {
          t(static_cast<Eigen::Index>(i)) = seq.frames[i].rgb_time;
          rgb.append(seq.frames[i].rgb_path);
          depth.append(seq.frames[i].depth_path);
        }
        d["timestamps"] = t, d["rgb"] = rgb, d["depth"] = depth;
        if (seq.groundtruth) {
          Eigen::VectorXd gt(seq.groundtruth->size());
          for (std::size_t i = 0; i < seq.groundtruth->size(); ++i)
            gt(static_cast<Eigen::Index>(i)) = (*seq.groundtruth)[i].timestamp;
          d["groundtruth"] = py::make_tuple(gt, poses(*seq.groundtruth));
        } else {
          d["groundtruth"] = py::none();
        }
        return d;
      },
      py::arg("path"), py::arg("max_association_dt") = 0.02,
      "A TUM sequence's frames (rgb timestamps and file paths), intrinsics, lens distortion (frames are undistorted at "
      "loading) and ground truth (timestamps, poses) or None.");

  om.def(
      "load_frame_pair",
      [](const std::string& path, int reference, int current, const py::kwargs& kwargs) {
        PyFramePair p;
        p.options = options_of(kwargs);
        py::gil_scoped_release release;
        p.pair = load_frame_pair(path, reference, current, p.options);
        return p;
      },
      py::arg("path"), py::arg("reference") = 0, py::arg("current") = 1,
      "Loads frames `reference` and `current` of a TUM sequence; keyword arguments are tracker options.");

  py::class_<TrackResult>(om, "TrackResult", "A tracked sequence (odometry/tracker.h): arrays per frame and per pair.")
      .def_readonly("sequence", &TrackResult::sequence)
      .def_property_readonly("timestamps",
                             [](const TrackResult& r) {
                               Eigen::VectorXd t(r.trajectory.size());
                               for (std::size_t i = 0; i < r.trajectory.size(); ++i)
                                 t(static_cast<Eigen::Index>(i)) = r.trajectory[i].timestamp;
                               return t;
                             })
      .def_property_readonly(
          "poses", [](const TrackResult& r) { return poses(r.trajectory); }, "T_wc per frame, N x 7")
      .def_readonly("pairs", &TrackResult::pairs)
      .def_readonly("invalid_pairs", &TrackResult::invalid_pairs)
      .def_property_readonly(
          "iterations",
          [](const TrackResult& r) { return pair_column(r.pairs, [](auto& p) { return double(p.iterations); }); })
      .def_property_readonly(
          "lambdas", [](const TrackResult& r) { return pair_column(r.pairs, [](auto& p) { return p.lambda; }); })
      .def_property_readonly(
          "epsilons", [](const TrackResult& r) { return pair_column(r.pairs, [](auto& p) { return p.epsilon; }); })
      .def_property_readonly("mus",
                             [](const TrackResult& r) { return pair_column(r.pairs, [](auto& p) { return p.mu; }); })
      .def_property_readonly("f_i",
                             [](const TrackResult& r) { return pair_column(r.pairs, [](auto& p) { return p.f_i; }); })
      .def_property_readonly("f_d",
                             [](const TrackResult& r) { return pair_column(r.pairs, [](auto& p) { return p.f_d; }); })
      .def_property_readonly(
          "seconds", [](const TrackResult& r) { return pair_column(r.pairs, [](auto& p) { return p.seconds; }); })
      .def_property_readonly("valid",
                             [](const TrackResult& r) {
                               return pair_column(r.pairs, [](auto& p) { return double(p.valid); }).cast<bool>().eval();
                             })
      .def_property_readonly(
          "translation_errors",
          [](const TrackResult& r) {
            return pair_column(r.pairs, [](auto& p) { return nan_if_absent(p.error, &io::PoseError::translation_m); });
          },
          "per pair |t| of truth^-1 * estimate in metres (NaN without ground truth)")
      .def_property_readonly(
          "rotation_errors_deg",
          [](const TrackResult& r) {
            return pair_column(r.pairs, [](auto& p) { return nan_if_absent(p.error, &io::PoseError::rotation_deg); });
          })
      .def_property_readonly("phases", [](const TrackResult& r) { return r.profile.all(); })
      .def(
          "write_trajectory",
          [](const TrackResult& r, const std::string& path) { io::write_tum_trajectory(path, r.trajectory); },
          py::arg("path"), "TUM trajectory file (what `bivo run` writes as estimate.txt)");

  const auto track = [](const std::string& path, const std::string& method, const std::string& backend,
                        py::kwargs kwargs) {
    kwargs["method"] = method;
    kwargs["backend"] = backend;
    const TrackerOptions o = options_of(kwargs);
    py::gil_scoped_release release;
    return track_sequence(path, o);
  };
  const char* track_doc =
      "Tracks a TUM sequence with a method and backend ('' = the method's default); other keyword "
      "arguments are tracker options (max_frames, levels, policy={...}, problem={...}, ...).";
  om.def("track", track, py::arg("path"), py::arg("method") = "weighted", py::arg("backend") = "", track_doc);
  m.def("track", track, py::arg("path"), py::arg("method") = "weighted", py::arg("backend") = "", track_doc);

  om.def(
      "render_synthetic",
      [](const std::string& output_dir, const std::string& category, int frames, std::uint64_t seed, bool noise,
         int threads) {
        synth::SynthOptions o;
        o.category = synth::parse_category(category);
        o.frames = frames;
        o.seed = seed;
        o.render.sensor_noise = noise;
        o.threads = threads;
        py::gil_scoped_release release;
        return synth::render_sequence(o, output_dir);
      },
      py::arg("output_dir"), py::arg("category") = "structure_texture_near", py::arg("frames") = 2, py::arg("seed") = 1,
      py::arg("noise") = true, py::arg("threads") = 0,
      "Renders a synthetic TUM-format sequence along generated hand-held motion (as `bivo synth`); returns its "
      "folder.");
}

}  // namespace bivo::python
