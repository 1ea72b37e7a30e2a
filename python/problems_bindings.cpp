// Problems in Python: the analytic instances of problems/ (submodule bivo.problems, with
// their closed-form oracles) and bivo.Problem, the base class a Python subclass fills with
// residuals and Jacobians (python_problem.h).
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "problems/exponential_decay_pair.h"
#include "problems/linear_least_squares_pair.h"
#include "problems/point_alignment_pair.h"
#include "python/bindings.h"
#include "python/python_problem.h"

namespace bivo::python {

void bind_problems(py::module_& m) {
  using problems::ExponentialDecayPair;
  using problems::LinearLeastSquaresPair;
  using problems::PointAlignmentPair;
  using solvers::BiObjectiveProblem;

  py::class_<PythonProblem, BiObjectiveProblem>(m, "Problem",
                                                R"(Base class of a bi-objective least-squares problem written in Python.

Subclass it, call super().__init__(dim, manifold="euclidean"|"se3", name=...) and define
  residual(self, j, x) -> r_j      1-D array, the same length m_j at every x (j = 1, 2)
  jacobian(self, j, x) -> J_j      m_j x dim: d r_j(x (+) d) / d d at d = 0
  weights(self, j)     -> w_j      optional, >= 0 (default: ones)
F_j = sum w_j r_j^2. On SE(3), x = [tx ty tz qx qy qz qw] and the perturbation is on the left,
x (+) d = exp(d) x with d = [v; w]. Every backend of bivo.backends() can then solve it.)")
      .def(py::init<int, const std::string&, std::string>(), py::arg("dim") = 0, py::arg("manifold") = "euclidean",
           py::arg("name") = "python problem")
      .def_property_readonly("callbacks", &PythonProblem::callbacks,
                             "Python calls made so far (residual, jacobian, weights)");

  auto pm = m.def_submodule("problems", "The analytic bi-objective instances of problems/ and their oracles.");

  py::class_<LinearLeastSquaresPair, BiObjectiveProblem>(
      pm, "LinearLeastSquaresPair",
      "F_j = (A_j x - y_j)^T diag(w_j) (A_j x - y_j); closed-form Pareto front (problems/linear_least_squares_pair.h).")
      .def(py::init([](const std::string& name, const py::object& A1, const py::object& y1, const py::object& w1,
                       const py::object& A2, const py::object& y2, const py::object& w2) {
             Eigen::MatrixXd a1 = matrix_arg(A1, "A1");
             Eigen::MatrixXd a2 = matrix_arg(A2, "A2", -1, a1.cols());
             return LinearLeastSquaresPair(name, a1, vector_arg(y1, "y1", a1.rows()), vector_arg(w1, "w1", a1.rows()),
                                           a2, vector_arg(y2, "y2", a2.rows()), vector_arg(w2, "w2", a2.rows()));
           }),
           py::arg("name"), py::arg("A1"), py::arg("y1"), py::arg("w1"), py::arg("A2"), py::arg("y2"), py::arg("w2"))
      .def_static("well_conditioned", &LinearLeastSquaresPair::well_conditioned, py::arg("n"), py::arg("seed"))
      .def_static("ill_conditioned", &LinearLeastSquaresPair::ill_conditioned, py::arg("n"), py::arg("seed"),
                  py::arg("condition") = 1e3)
      .def_property_readonly("dim", &LinearLeastSquaresPair::dim)
      .def(
          "objectives",
          [](const LinearLeastSquaresPair& p, const py::object& x) {
            return p.objectives(vector_arg(x, "x", p.dim()));
          },
          py::arg("x"))
      .def(
          "weighted_sum_optimum",
          [](const LinearLeastSquaresPair& p, double lam) {
            if (!(lam >= 0.0)) throw py::value_error("lam must be >= 0");
            return p.weighted_sum_optimum(lam);
          },
          py::arg("lam"), "argmin F1 + lam F2 by Householder QR of the stacked system")
      .def(
          "minimizer",
          [](const LinearLeastSquaresPair& p, int j) {
            if (j != 1 && j != 2) throw py::value_error("j must be 1 or 2");
            return p.minimizer(j);
          },
          py::arg("j"))
      .def(
          "epsilon_constraint_optimum",
          [](const LinearLeastSquaresPair& p, double epsilon) {
            const auto o = p.epsilon_constraint_optimum(epsilon);
            return py::make_tuple(o.x, o.mu, o.feasible);
          },
          py::arg("epsilon"), "(x, mu, feasible) of min F1 s.t. F2 <= epsilon");

  py::class_<ExponentialDecayPair, BiObjectiveProblem>(
      pm, "ExponentialDecayPair",
      "Two exponential-decay fits sharing one rate, x = [c1, c2, k] (problems/exponential_decay_pair.h).")
      .def(py::init([](const py::object& t1, const py::object& y1, const py::object& w1, const py::object& t2,
                       const py::object& y2, const py::object& w2) {
             const Eigen::VectorXd a = vector_arg(t1, "t1"), b = vector_arg(t2, "t2");
             return ExponentialDecayPair(a, vector_arg(y1, "y1", a.size()), vector_arg(w1, "w1", a.size()), b,
                                         vector_arg(y2, "y2", b.size()), vector_arg(w2, "w2", b.size()));
           }),
           py::arg("t1"), py::arg("y1"), py::arg("w1"), py::arg("t2"), py::arg("y2"), py::arg("w2"))
      .def_static("synthetic", &ExponentialDecayPair::synthetic, py::arg("m"), py::arg("seed"))
      .def("weighted_sum_optimum", &ExponentialDecayPair::weighted_sum_optimum, py::arg("lam"), py::arg("k_lo") = 0.05,
           py::arg("k_hi") = 5.0, "argmin F1 + lam F2 by variable projection and bisection");

  py::class_<PointAlignmentPair, BiObjectiveProblem>(
      pm, "PointAlignmentPair",
      "Two point-set alignments on SE(3) pulling to different poses (problems/point_alignment_pair.h).")
      .def(py::init<std::uint64_t>(), py::arg("seed"));
}

}  // namespace bivo::python
