// bivo.metrics: the TUM benchmark's RPE and ATE (odometry/io/metrics.h, docs/metrics.md) on
// trajectories given as arrays (timestamps N, poses N x 7 [t; q]) or as TUM files.
#include <sstream>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "experiments/trajectory_evaluation.h"
#include "odometry/io/metrics.h"
#include "python/bindings.h"
#include "solvers/geometry/se3.h"

namespace bivo::python {
namespace {

using namespace odometry::io;

Trajectory trajectory_arg(const py::handle& times, const py::handle& poses, const std::string& name) {
  const Eigen::VectorXd t = vector_arg(times, name + " timestamps");
  const Eigen::MatrixXd P = matrix_arg(poses, name + " poses", t.size(), 7);
  Trajectory out(t.size());
  for (Eigen::Index i = 0; i < t.size(); ++i) {
    if (i > 0 && !(t(i) > t(i - 1))) {
      std::ostringstream msg;
      msg << name << " timestamps: not strictly increasing at index " << i << " (" << t(i - 1) << ", " << t(i) << ")";
      throw py::value_error(msg.str());
    }
    if (P.row(i).tail<4>().norm() < 1e-12) {
      throw py::value_error(name + " poses: row " + std::to_string(i) + " has a zero quaternion");
    }
    out[i].timestamp = t(i);
    out[i].T_wc = solvers::se3::from_ambient(P.row(i).transpose());
  }
  return out;
}

py::dict rpe_dict(const RpeResult& r) {
  py::dict d;
  d["trans_rmse"] = r.trans_rmse, d["trans_mean"] = r.trans_mean, d["trans_median"] = r.trans_median;
  d["trans_max"] = r.trans_max, d["rot_rmse_deg"] = r.rot_rmse_deg, d["rot_mean_deg"] = r.rot_mean_deg;
  d["rot_max_deg"] = r.rot_max_deg;
  Eigen::VectorXd trans(r.pairs.size()), rot(r.pairs.size()), t0(r.pairs.size()), t1(r.pairs.size());
  for (std::size_t i = 0; i < r.pairs.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    trans(k) = r.pairs[i].trans, rot(k) = r.pairs[i].rot_rad * 180.0 / M_PI;
    t0(k) = r.pairs[i].t_est_0, t1(k) = r.pairs[i].t_est_1;
  }
  d["trans"] = trans, d["rot_deg"] = rot, d["t_start"] = t0, d["t_end"] = t1;
  return d;
}

py::dict ate_dict(const AteResult& a) {
  py::dict d;
  d["rmse"] = a.rmse, d["mean"] = a.mean, d["median"] = a.median, d["max"] = a.max;
  d["errors"] =
      Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(a.errors.data(), static_cast<Eigen::Index>(a.errors.size())));
  d["t_est"] =
      Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(a.t_est.data(), static_cast<Eigen::Index>(a.t_est.size())));
  d["alignment"] = Eigen::Matrix4d(a.alignment.matrix());
  return d;
}

}  // namespace

void bind_metrics(py::module_& m) {
  auto mm = m.def_submodule("metrics", "TUM RPE / ATE (odometry/io/metrics.h, docs/metrics.md).");
  mm.def(
      "read_trajectory",
      [](const std::string& path) {
        const Trajectory t = read_tum_trajectory(path);
        Eigen::VectorXd times(t.size());
        Eigen::MatrixXd poses(t.size(), 7);
        for (std::size_t i = 0; i < t.size(); ++i) {
          times(static_cast<Eigen::Index>(i)) = t[i].timestamp;
          poses.row(static_cast<Eigen::Index>(i)) = solvers::se3::to_ambient(t[i].T_wc).transpose();
        }
        return py::make_tuple(times, poses);
      },
      py::arg("path"), "A TUM trajectory file as (timestamps, poses N x 7).");
  mm.def(
      "rpe",
      [](const py::object& gt_t, const py::object& gt_poses, const py::object& est_t, const py::object& est_poses,
         double delta, double max_dt) {
        RpeOptions o;
        o.delta_s = delta;
        o.max_dt = max_dt;
        return rpe_dict(relative_pose_error(trajectory_arg(gt_t, gt_poses, "groundtruth"),
                                            trajectory_arg(est_t, est_poses, "estimate"), o));
      },
      py::arg("gt_timestamps"), py::arg("gt_poses"), py::arg("est_timestamps"), py::arg("est_poses"),
      py::arg("delta") = 1.0, py::arg("max_dt") = 0.02,
      "Relative pose error over windows of `delta` seconds: a dict of statistics (m, deg) and per-window arrays.");
  mm.def(
      "ate",
      [](const py::object& gt_t, const py::object& gt_poses, const py::object& est_t, const py::object& est_poses,
         double max_dt) {
        AteOptions o;
        o.max_dt = max_dt;
        return ate_dict(absolute_trajectory_error(trajectory_arg(gt_t, gt_poses, "groundtruth"),
                                                  trajectory_arg(est_t, est_poses, "estimate"), o));
      },
      py::arg("gt_timestamps"), py::arg("gt_poses"), py::arg("est_timestamps"), py::arg("est_poses"),
      py::arg("max_dt") = 0.02,
      "Absolute trajectory error after rigid alignment: statistics, errors, alignment (4x4).");
  mm.def(
      "evaluate_files",
      [](const std::string& groundtruth, const std::string& estimate, double delta, double max_dt) {
        const experiments::TrajectoryEvaluation e =
            experiments::evaluate_trajectory_files(groundtruth, estimate, delta, max_dt);
        py::dict d;
        d["rpe"] = rpe_dict(e.rpe);
        d["ate"] = ate_dict(e.ate);
        d["line"] = experiments::evaluation_line(e, false);
        return d;
      },
      py::arg("groundtruth"), py::arg("estimate"), py::arg("delta") = 1.0, py::arg("max_dt") = 0.02,
      "RPE and ATE of two TUM files, as `bivo eval` computes them (with its one-line summary).");
}

}  // namespace bivo::python
