// bivo.Problem's C++ side: calls the Python subclass's residual / jacobian / weights and
// checks what they return (python_problem.h).
#include "python/python_problem.h"

#include <sstream>

#include <pybind11/numpy.h>

#include "solvers/error.h"

namespace bivo::python {

PythonProblem::PythonProblem(int dim, const std::string& manifold, std::string name) : name_(std::move(name)) {
  if (manifold == "euclidean") {
    if (dim < 1)
      throw py::value_error("bivo.Problem: dim must be >= 1 for a Euclidean problem, got " + std::to_string(dim));
    manifold_ = std::make_unique<solvers::EuclideanManifold>(dim);
  } else if (manifold == "se3") {
    if (dim != 6 && dim != 0)
      throw py::value_error("bivo.Problem: an SE(3) problem has dim 6 (tangent), got " + std::to_string(dim));
    manifold_ = std::make_unique<solvers::Se3Manifold>();
  } else {
    throw py::value_error("bivo.Problem: manifold must be 'euclidean' or 'se3', got '" + manifold + "'");
  }
}

py::object PythonProblem::method(const char* name) const {
  py::function f = py::get_override(static_cast<const PythonProblem*>(this), name);
  if (!f) {
    throw py::type_error("bivo.Problem '" + name_ + "': the subclass must define " + name + "()");
  }
  return std::move(f);
}

void PythonProblem::rethrow_pending() {
  if (!pending_) return;
  std::exception_ptr e = pending_;
  pending_ = nullptr;
  std::rethrow_exception(e);
}

solvers::ResidualData PythonProblem::call(int j, const Eigen::VectorXd& x, bool with_jacobian) {
  const std::string where = "bivo.Problem '" + name_ + "': ";
  solvers::ResidualData d;
  const py::array_t<double> xa(x.size(), x.data());
  ++callbacks_;
  const py::object r = method("residual")(j, xa);
  d.r = vector_arg(r, where + "residual(" + std::to_string(j) + ", x)", rows_[j - 1], /*finite=*/false);
  rows_[j - 1] = d.r.size();
  if (with_jacobian) {
    ++callbacks_;
    const py::object J = method("jacobian")(j, xa);
    d.J = matrix_arg(J, where + "jacobian(" + std::to_string(j) + ", x)", d.r.size(), manifold_->tangent_dim(),
                     /*finite=*/false);
  }
  py::function weights = py::get_override(static_cast<const PythonProblem*>(this), "weights");
  if (weights) {
    ++callbacks_;
    d.w = vector_arg(weights(j), where + "weights(" + std::to_string(j) + ")", d.r.size());
    if ((d.w.array() < 0.0).any())
      throw py::value_error(where + "weights(" + std::to_string(j) + ") has negative entries");
  } else {
    d.w = Eigen::VectorXd::Ones(d.r.size());
  }
  return d;
}

solvers::ResidualData PythonProblem::residuals(int j, const Eigen::VectorXd& x, bool with_jacobian) {
  if (j != 1 && j != 2)
    throw Error("bivo.Problem '" + name_ + "': objective index must be 1 or 2, got " + std::to_string(j));
  py::gil_scoped_acquire gil;
  try {
    return call(j, x, with_jacobian);
  } catch (...) {
    // Kept for the solve wrapper (a backend may catch what is thrown through it); the
    // bivo::Error below stops the solver where exceptions pass.
    if (!pending_) pending_ = std::current_exception();
    throw Error("bivo.Problem '" + name_ + "': a Python callback failed (re-raised once the solver returns)");
  }
}

solvers::Linearization PythonProblem::linearize(const Eigen::VectorXd& x, const solvers::LinearizeOptions& options) {
  return solvers::linearize_from_residuals(*this, x, options);
}

std::array<double, 2> PythonProblem::evaluate(const Eigen::VectorXd& x) {
  std::array<double, 2> f{};
  for (int j = 1; j <= 2; ++j) {
    const solvers::ResidualData d = residuals(j, x, false);
    f[j - 1] = d.r.dot(d.w.cwiseProduct(d.r));
  }
  return f;
}

}  // namespace bivo::python
