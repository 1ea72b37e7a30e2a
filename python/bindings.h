#pragma once
// What the binding files of the Python module `bivo` share: one bind_* function per layer
// (module.cpp calls them in layer order) and the checks every array argument goes through.
// Arrays are converted by pybind11's numpy/Eigen support; before that, an argument's dtype,
// shape and finiteness are checked here so a bad array is a ValueError naming the argument,
// never a crash or an error deep inside a solver.
#include <string>

#include <pybind11/pybind11.h>
#include <Eigen/Core>

namespace bivo::python {

namespace py = pybind11;

void bind_solvers(py::module_& m);   // backends, options, scalarizations, summary, solve, Pareto
void bind_conic(py::module_& m);     // the conic IPM on (c, G, h, A, b, cones)
void bind_problems(py::module_& m);  // analytic instances and the Python-subclassable bivo.Problem
void bind_odometry(py::module_& m);  // frame pairs, per-pair problems, track(), synthetic sequences
void bind_metrics(py::module_& m);   // RPE / ATE (the submodule bivo.metrics)

// A real (float, int or bool dtype) array converted to double; ValueError naming `name`
// otherwise. `size` < 0: any length. `finite`: NaN/Inf entries are a ValueError too.
Eigen::VectorXd vector_arg(const py::handle& value, const std::string& name, Eigen::Index size = -1,
                           bool finite = true);
// The same for a 2-D array; rows / cols < 0: any.
Eigen::MatrixXd matrix_arg(const py::handle& value, const std::string& name, Eigen::Index rows = -1,
                           Eigen::Index cols = -1, bool finite = true);

}  // namespace bivo::python
