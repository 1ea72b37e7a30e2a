#pragma once
// bivo.Problem: a BiObjectiveProblem whose residuals, Jacobians and weights come from
// methods of a Python subclass:
//   residual(j, x) -> r_j (1-D, length m_j fixed for the problem)
//   jacobian(j, x) -> J_j (m_j x tangent_dim): d r_j(x (+) d) / d d at d = 0
//   weights(j)     -> w_j (optional; default all ones)
// The models (a, b, H) and F_j = r^T diag(w) r are formed in C++ from these arrays.
//
// GIL: every callback takes the GIL (solve() releases it around the C++ solver, so other
// Python threads run while a C++ problem is solved). A Python exception or a bad array in a
// callback is kept and re-raised by solve()/pareto_sweep() once the solver returns: a
// backend that catches exceptions itself (Ipopt) cannot swallow it, and one that does not
// (the outer loop) stops at once on the bivo::Error thrown in its place.
#include <exception>
#include <memory>
#include <string>

#include "python/bindings.h"
#include "solvers/problem.h"

namespace bivo::python {

class PythonProblem : public solvers::BiObjectiveProblem {
 public:
  // manifold: "euclidean" (x in R^dim) or "se3" (dim must be 6 or omitted: x = [t; q], 7 numbers).
  PythonProblem(int dim, const std::string& manifold, std::string name);

  std::string name() const override { return name_; }
  const solvers::Manifold& manifold() const override { return *manifold_; }
  solvers::Linearization linearize(const Eigen::VectorXd& x, const solvers::LinearizeOptions& options) override;
  std::array<double, 2> evaluate(const Eigen::VectorXd& x) override;
  solvers::ResidualData residuals(int j, const Eigen::VectorXd& x, bool with_jacobian) override;

  // Called by the solve wrappers around a C++ solve.
  void clear_pending() { pending_ = nullptr; }
  void rethrow_pending();                        // re-raises the first callback error since clear_pending()
  long callbacks() const { return callbacks_; }  // Python calls made (residual, jacobian, weights)

 private:
  py::object method(const char* name) const;  // the subclass's override; error if missing
  solvers::ResidualData call(int j, const Eigen::VectorXd& x, bool with_jacobian);

  std::string name_;
  std::unique_ptr<solvers::Manifold> manifold_;
  std::exception_ptr pending_;
  long callbacks_ = 0;
  Eigen::Index rows_[2] = {-1, -1};  // m_j, fixed by the first call
};

// Runs `body` (a C++ solve) without the GIL when the problem is a PythonProblem's or not,
// and re-raises a callback error afterwards.
template <class Body>
auto run_solver(solvers::BiObjectiveProblem& problem, Body&& body) {
  auto* python_problem = dynamic_cast<PythonProblem*>(&problem);
  if (python_problem) python_problem->clear_pending();
  try {
    py::gil_scoped_release release;
    auto result = body();
    py::gil_scoped_acquire acquire;
    if (python_problem) python_problem->rethrow_pending();
    return result;
  } catch (...) {
    if (python_problem) python_problem->rethrow_pending();
    throw;
  }
}

}  // namespace bivo::python
