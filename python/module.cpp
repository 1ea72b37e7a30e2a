// The Python module `bivo`: bivo::Error becomes bivo.Error (a RuntimeError carrying the
// C++ message), bad array arguments become ValueError (vector_arg / matrix_arg below), and
// each layer's bindings are added in layer order (solvers, problems, odometry, metrics).
#include <cmath>
#include <sstream>
#include <string>

#include <pybind11/numpy.h>

#include "python/bindings.h"
#include "solvers/error.h"

namespace bivo::python {
namespace {

py::array real_array(const py::handle& value, const std::string& name, int ndim) {
  py::array a = py::array::ensure(value);
  if (!a)
    throw py::value_error(name + ": expected an array of real numbers, got " +
                          std::string(py::str(py::type::of(value))));
  const char kind = a.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u' && kind != 'b') {
    throw py::value_error(name + ": expected real numbers, got dtype " + std::string(py::str(a.dtype())));
  }
  if (a.ndim() != ndim) {
    std::ostringstream msg;
    msg << name << ": expected a " << ndim << "-D array, got " << a.ndim() << "-D";
    throw py::value_error(msg.str());
  }
  return a;
}

void check_finite(const double* data, Eigen::Index count, const std::string& name) {
  for (Eigen::Index i = 0; i < count; ++i) {
    if (!std::isfinite(data[i])) {
      std::ostringstream msg;
      msg << name << ": entry " << i << " (row-major) is " << data[i] << "; NaN/Inf are not accepted";
      throw py::value_error(msg.str());
    }
  }
}

}  // namespace

Eigen::VectorXd vector_arg(const py::handle& value, const std::string& name, Eigen::Index size, bool finite) {
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(real_array(value, name, 1));
  if (size >= 0 && a.shape(0) != size) {
    std::ostringstream msg;
    msg << name << ": expected " << size << " entries, got " << a.shape(0);
    throw py::value_error(msg.str());
  }
  if (finite) check_finite(a.data(), a.shape(0), name);
  return Eigen::Map<const Eigen::VectorXd>(a.data(), a.shape(0));
}

Eigen::MatrixXd matrix_arg(const py::handle& value, const std::string& name, Eigen::Index rows, Eigen::Index cols,
                           bool finite) {
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(real_array(value, name, 2));
  if ((rows >= 0 && a.shape(0) != rows) || (cols >= 0 && a.shape(1) != cols)) {
    std::ostringstream msg;
    msg << name << ": expected shape (" << (rows >= 0 ? std::to_string(rows) : "any") << ", "
        << (cols >= 0 ? std::to_string(cols) : "any") << "), got (" << a.shape(0) << ", " << a.shape(1) << ")";
    throw py::value_error(msg.str());
  }
  if (finite) check_finite(a.data(), a.size(), name);
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  return Eigen::Map<const RowMajor>(a.data(), a.shape(0), a.shape(1));
}

}  // namespace bivo::python

PYBIND11_MODULE(bivo, m) {
  namespace bp = bivo::python;
  m.doc() = "bivo: bi-objective least squares (solver backends, Pareto fronts, conic IPM) and RGB-D odometry";
  bp::py::register_exception<bivo::Error>(m, "Error", PyExc_RuntimeError);
  bp::bind_solvers(m);
  bp::bind_conic(m);
  bp::bind_problems(m);
  bp::bind_odometry(m);
  bp::bind_metrics(m);
  // `import bivo.metrics` / `from bivo.odometry import track` find the submodules too.
  auto modules = bp::py::module_::import("sys").attr("modules");
  for (const char* sub : {"problems", "odometry", "metrics"})
    modules[(std::string("bivo.") + sub).c_str()] = m.attr(sub);
}
