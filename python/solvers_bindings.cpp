// The solver layer in Python: backends by name, SolverOptions, the two scalarizations, the
// problem interface (evaluate / residuals / linearize on any problem), solve() and its
// Summary, and Pareto sweeps with knee and hypervolume (docs/python.md).
#include <limits>
#include <sstream>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "python/bindings.h"
#include "python/python_problem.h"
#include "solvers/backend_registry.h"
#include "solvers/outer_loop.h"
#include "solvers/pareto.h"

namespace bivo::python {
namespace {

using namespace solvers;

SolverOptions options_arg(const py::object& options) {
  if (options.is_none()) return SolverOptions{};
  if (py::isinstance<SolverOptions>(options)) return options.cast<SolverOptions>();
  throw py::value_error("options: expected a bivo.SolverOptions or None, got " +
                        std::string(py::str(py::type::of(options))));
}

std::string kind_name(ScalarizationKind k) {
  return k == ScalarizationKind::kWeightedSum ? "weighted-sum" : "epsilon-constraint";
}

template <class T, class F>
Eigen::Matrix<T, Eigen::Dynamic, 1> column(const std::vector<IterationRecord>& records, F field) {
  Eigen::Matrix<T, Eigen::Dynamic, 1> v(records.size());
  for (std::size_t i = 0; i < records.size(); ++i) v(static_cast<Eigen::Index>(i)) = static_cast<T>(field(records[i]));
  return v;
}

Eigen::MatrixXd iterates(const Summary& s) {
  const Eigen::Index n = s.records.empty() ? 0 : s.records.front().x.size();
  Eigen::MatrixXd X(s.records.size(), n);
  for (std::size_t i = 0; i < s.records.size(); ++i) X.row(static_cast<Eigen::Index>(i)) = s.records[i].x.transpose();
  return X;
}

// The Pareto front with the hypervolume's reference point, as Python sees it.
struct Front {
  ParetoFront front;
  double ref_f1 = 0.0, ref_f2 = 0.0;
};

template <class F>
Eigen::VectorXd point_column(const std::vector<ParetoPoint>& points, F field) {
  Eigen::VectorXd v(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) v(static_cast<Eigen::Index>(i)) = field(points[i]);
  return v;
}

std::vector<ParetoPoint> points_of(const py::handle& f1, const py::handle& f2) {
  const Eigen::VectorXd a = vector_arg(f1, "f1");
  const Eigen::VectorXd b = vector_arg(f2, "f2", a.size());
  std::vector<ParetoPoint> points(a.size());
  for (Eigen::Index i = 0; i < a.size(); ++i) points[i].f1 = a(i), points[i].f2 = b(i);
  return points;
}

Eigen::VectorXd x_arg(const BiObjectiveProblem& problem, const py::handle& x, const char* name = "x") {
  return vector_arg(x, name, problem.manifold().ambient_dim());
}

}  // namespace

void bind_solvers(py::module_& m) {
  m.def(
      "backends",
      [] {
        py::list out;
        for (const BackendInfo& b : backend_infos()) {
          py::dict d;
          d["name"] = b.name;
          d["description"] = b.description;
          d["whole_problem"] = b.whole_problem;
          d["weighted_sum"] = b.weighted_sum;
          d["epsilon_constraint"] = b.epsilon_constraint;
          out.append(d);
        }
        return out;
      },
      "The solver backends in registration order: dicts with name, description, whole_problem, "
      "weighted_sum, epsilon_constraint (which scalarizations the backend solves).");

  py::class_<SolverOptions>(m, "SolverOptions", "What one solve is told (solvers/summary.h).")
      .def(py::init([](int max_iterations, double step_tolerance, double relative_decrease_tolerance, int verbosity,
                       bool want_full_residuals) {
             SolverOptions o;
             o.max_iterations = max_iterations;
             o.step_tolerance = step_tolerance;
             o.relative_decrease_tolerance = relative_decrease_tolerance;
             o.verbosity = verbosity;
             o.want_full_residuals = want_full_residuals;
             return o;
           }),
           py::arg("max_iterations") = 50, py::arg("step_tolerance") = 1e-10,
           py::arg("relative_decrease_tolerance") = 1e-12, py::arg("verbosity") = 0,
           py::arg("want_full_residuals") = false)
      .def_readwrite("max_iterations", &SolverOptions::max_iterations)
      .def_readwrite("step_tolerance", &SolverOptions::step_tolerance)
      .def_readwrite("relative_decrease_tolerance", &SolverOptions::relative_decrease_tolerance)
      .def_readwrite("verbosity", &SolverOptions::verbosity)
      .def_readwrite("want_full_residuals", &SolverOptions::want_full_residuals)
      .def_readwrite("max_step_extrapolation", &SolverOptions::max_step_extrapolation,
                     "largest factor a steadily shrinking step is extrapolated by (1 = off)");

  py::class_<Scalarization>(m, "Scalarization", "Base of WeightedSum and EpsilonConstraint.")
      .def_property_readonly("kind", [](const Scalarization& s) { return kind_name(s.kind()); })
      .def("describe", &Scalarization::describe)
      .def("__repr__", &Scalarization::describe);
  py::class_<WeightedSum, Scalarization>(m, "WeightedSum", "min F1 + lambda F2 (lambda >= 0; bivo.Error otherwise).")
      .def(py::init<double>(), py::arg("lam"))
      .def_property_readonly("lam", &WeightedSum::fixed_lambda);
  py::class_<EpsilonConstraint, Scalarization>(m, "EpsilonConstraint", "min F1 s.t. F2 <= epsilon (epsilon >= 0).")
      .def(py::init<double>(), py::arg("epsilon"))
      .def_property_readonly("epsilon", &EpsilonConstraint::fixed_epsilon);

  py::class_<BiObjectiveProblem>(m, "BiObjectiveProblem",
                                 "Two weighted least-squares objectives on a manifold (solvers/problem.h).")
      .def_property_readonly("name", &BiObjectiveProblem::name)
      .def_property_readonly("ambient_dim", [](const BiObjectiveProblem& p) { return p.manifold().ambient_dim(); })
      .def_property_readonly("tangent_dim", [](const BiObjectiveProblem& p) { return p.manifold().tangent_dim(); })
      .def_property_readonly("manifold",
                             [](const BiObjectiveProblem& p) -> std::string {
                               if (dynamic_cast<const Se3Manifold*>(&p.manifold())) return "se3";
                               if (dynamic_cast<const EuclideanManifold*>(&p.manifold())) return "euclidean";
                               return "other";
                             })
      .def(
          "evaluate",
          [](BiObjectiveProblem& p, const py::object& x) {
            const Eigen::VectorXd xv = x_arg(p, x);
            return run_solver(p, [&] { return p.evaluate(xv); });
          },
          py::arg("x"), "(F1, F2) at x with the weights of the latest linearize().")
      .def(
          "residuals",
          [](BiObjectiveProblem& p, int j, const py::object& x, bool jacobian) {
            if (j != 1 && j != 2) throw py::value_error("j: objective index must be 1 or 2, got " + std::to_string(j));
            const Eigen::VectorXd xv = x_arg(p, x);
            const ResidualData d = run_solver(p, [&] { return p.residuals(j, xv, jacobian); });
            return py::make_tuple(d.r, d.J, d.w);
          },
          py::arg("j"), py::arg("x"), py::arg("jacobian") = true, "(r_j, J_j, w_j) at x; J empty without jacobian.")
      .def(
          "linearize",
          [](BiObjectiveProblem& p, const py::object& x, bool update_weights) {
            const Eigen::VectorXd xv = x_arg(p, x);
            LinearizeOptions lo;
            lo.update_weights = update_weights;
            const Linearization lin = run_solver(p, [&] { return p.linearize(xv, lo); });
            py::dict d;
            d["a1"] = lin.f1.a, d["b1"] = lin.f1.b, d["H1"] = lin.f1.H;
            d["a2"] = lin.f2.a, d["b2"] = lin.f2.b, d["H2"] = lin.f2.H;
            return d;
          },
          py::arg("x"), py::arg("update_weights") = true,
          "Both quadratic models at x: F_j(x (+) d) ~ a_j + 2 b_j.d + d.H_j d, as a dict a1 b1 H1 a2 b2 H2.")
      .def(
          "retract",
          [](const BiObjectiveProblem& p, const py::object& x, const py::object& delta) {
            return p.manifold().retract(x_arg(p, x), vector_arg(delta, "delta", p.manifold().tangent_dim()));
          },
          py::arg("x"), py::arg("delta"), "x (+) delta on the problem's manifold.");

  py::class_<Summary>(m, "Summary", py::dynamic_attr(),
                      "What one solve reports (solvers/summary.h); x is the solution.")
      .def_readonly("problem", &Summary::problem)
      .def_readonly("backend", &Summary::backend)
      .def_property_readonly("kind", [](const Summary& s) { return kind_name(s.kind); })
      .def_readonly("scalarization", &Summary::scalarization)
      .def_readonly("iterations", &Summary::iterations)
      .def_readonly("extrapolated_steps", &Summary::extrapolated_steps)
      .def_readonly("refused_extrapolations", &Summary::refused_extrapolations)
      .def_readonly("initial_f1", &Summary::initial_f1)
      .def_readonly("initial_f2", &Summary::initial_f2)
      .def_readonly("final_f1", &Summary::final_f1)
      .def_readonly("final_f2", &Summary::final_f2)
      .def_readonly("multiplier", &Summary::multiplier)
      .def_readonly("epsilon", &Summary::epsilon)
      .def_readonly("feasible", &Summary::feasible)
      .def_property_readonly("termination", [](const Summary& s) { return std::string(to_string(s.termination)); })
      .def_readonly("message", &Summary::message)
      .def_property_readonly("converged", &Summary::converged)
      .def_readonly("total_seconds", &Summary::total_seconds)
      .def_property_readonly("phases", [](const Summary& s) { return s.phases.all(); })
      .def_property_readonly("f1",
                             [](const Summary& s) { return column<double>(s.records, [](auto& r) { return r.f1; }); })
      .def_property_readonly("f2",
                             [](const Summary& s) { return column<double>(s.records, [](auto& r) { return r.f2; }); })
      .def_property_readonly(
          "multipliers",
          [](const Summary& s) { return column<double>(s.records, [](auto& r) { return r.multiplier; }); })
      .def_property_readonly(
          "epsilons", [](const Summary& s) { return column<double>(s.records, [](auto& r) { return r.epsilon; }); })
      .def_property_readonly(
          "step_norms", [](const Summary& s) { return column<double>(s.records, [](auto& r) { return r.step_norm; }); })
      .def_property_readonly(
          "step_scales",
          [](const Summary& s) { return column<double>(s.records, [](auto& r) { return r.step_scale; }); })
      .def_property_readonly(
          "accepted", [](const Summary& s) { return column<bool>(s.records, [](auto& r) { return r.accepted; }); })
      .def_property_readonly(
          "feasible_steps",
          [](const Summary& s) { return column<bool>(s.records, [](auto& r) { return r.feasible; }); })
      .def_property_readonly(
          "inner_iterations",
          [](const Summary& s) { return column<int>(s.records, [](auto& r) { return r.inner_iterations; }); })
      .def_property_readonly(
          "iteration_seconds",
          [](const Summary& s) { return column<double>(s.records, [](auto& r) { return r.seconds; }); })
      .def_property_readonly("iterates", &iterates, "x after each iteration, one row per iteration")
      .def("brief_report", &Summary::BriefReport)
      .def("full_report", &Summary::FullReport)
      .def("__repr__", &Summary::BriefReport);

  m.def(
      "solve",
      [](BiObjectiveProblem& problem, const Scalarization& scalarization, const std::string& backend,
         const py::object& x0, const py::object& options) {
        Eigen::VectorXd x = x_arg(problem, x0, "x0");
        const SolverOptions o = options_arg(options);
        const std::string b = backend.empty() ? default_backend(scalarization.kind()) : backend;
        Summary s = run_solver(problem, [&] { return solve(problem, scalarization, b, x, o); });
        py::object out = py::cast(std::move(s));
        out.attr("x") = x;
        out.attr("x0") = x_arg(problem, x0, "x0");
        return out;
      },
      py::arg("problem"), py::arg("scalarization"), py::arg("backend"), py::arg("x0"), py::arg("options") = py::none(),
      "Solves problem with the scalarization by the named backend ('' = gn / exact) from x0; returns a Summary "
      "whose x is the solution.");

  py::class_<Front>(m, "ParetoFront", "A swept front: non-dominated points sorted by f1 (solvers/pareto.h).")
      .def_property_readonly("f1",
                             [](const Front& f) { return point_column(f.front.points, [](auto& p) { return p.f1; }); })
      .def_property_readonly("f2",
                             [](const Front& f) { return point_column(f.front.points, [](auto& p) { return p.f2; }); })
      .def_property_readonly(
          "parameters",
          [](const Front& f) { return point_column(f.front.points, [](auto& p) { return p.parameter; }); })
      .def_property_readonly(
          "multipliers",
          [](const Front& f) { return point_column(f.front.points, [](auto& p) { return p.multiplier; }); })
      .def_property_readonly(
          "iterations",
          [](const Front& f) {
            return point_column(f.front.points, [](auto& p) { return double(p.iterations); }).cast<int>().eval();
          })
      .def_property_readonly(
          "converged",
          [](const Front& f) {
            return point_column(f.front.points, [](auto& p) { return double(p.converged); }).cast<bool>().eval();
          })
      .def_property_readonly(
          "x",
          [](const Front& f) {
            Eigen::MatrixXd X(f.front.points.size(), f.front.points.empty() ? 0 : f.front.points[0].x.size());
            for (std::size_t i = 0; i < f.front.points.size(); ++i)
              X.row(static_cast<Eigen::Index>(i)) = f.front.points[i].x.transpose();
            return X;
          },
          "one solution per row")
      .def_property_readonly("all_f1",
                             [](const Front& f) { return point_column(f.front.all, [](auto& p) { return p.f1; }); })
      .def_property_readonly("all_f2",
                             [](const Front& f) { return point_column(f.front.all, [](auto& p) { return p.f2; }); })
      .def_property_readonly(
          "all_parameters",
          [](const Front& f) { return point_column(f.front.all, [](auto& p) { return p.parameter; }); })
      .def_property_readonly("dropped", [](const Front& f) { return f.front.dropped; })
      .def_property_readonly("f2_min", [](const Front& f) { return f.front.f2_min; })
      .def_property_readonly("f2_at_f1_min", [](const Front& f) { return f.front.f2_at_f1_min; })
      .def_property_readonly(
          "knee",
          [](const Front& f) -> py::object {
            const auto k = knee_index(f.front.points);
            return k ? py::object(py::int_(*k)) : py::object(py::none());
          },
          "index of the knee point (normalized distance to the chord), None with < 3 points")
      .def_property_readonly("reference", [](const Front& f) { return py::make_tuple(f.ref_f1, f.ref_f2); })
      .def_property_readonly(
          "hypervolume", [](const Front& f) { return hypervolume(f.front.points, f.ref_f1, f.ref_f2); },
          "area dominated by the front up to `reference`")
      .def("__len__", [](const Front& f) { return f.front.points.size(); });

  m.def(
      "pareto_sweep",
      [](BiObjectiveProblem& problem, const py::object& x0, const std::string& scalarization, int points,
         const std::string& backend, double lambda_min, double lambda_max, const py::object& options,
         const py::object& reference) {
        const Eigen::VectorXd x = x_arg(problem, x0, "x0");
        ParetoOptions o;
        o.points = points;
        o.lambda_min = lambda_min;
        o.lambda_max = lambda_max;
        o.backend = backend;
        o.solver = options_arg(options);
        if (scalarization != "epsilon" && scalarization != "lambda") {
          throw py::value_error(
              "scalarization: 'epsilon' (epsilon-constraint sweep) or 'lambda' (weighted sum), got '" + scalarization +
              "'");
        }
        Front f;
        f.front = run_solver(problem, [&] {
          return scalarization == "epsilon" ? sweep_epsilon(problem, x, o) : sweep_lambda(problem, x, o);
        });
        if (reference.is_none()) {  // the nadir point of the front
          f.ref_f1 = f.ref_f2 = -std::numeric_limits<double>::infinity();
          for (const ParetoPoint& p : f.front.points)
            f.ref_f1 = std::max(f.ref_f1, p.f1), f.ref_f2 = std::max(f.ref_f2, p.f2);
        } else {
          const Eigen::VectorXd r = vector_arg(reference, "reference", 2);
          f.ref_f1 = r(0), f.ref_f2 = r(1);
        }
        return f;
      },
      py::arg("problem"), py::arg("x0"), py::arg("scalarization") = "epsilon", py::arg("points") = 21,
      py::arg("backend") = "", py::arg("lambda_min") = 1e-3, py::arg("lambda_max") = 1e3,
      py::arg("options") = py::none(), py::arg("reference") = py::none(),
      "Sweeps epsilon (uniform over [min F2, F2 at argmin F1]) or lambda (log grid); warm-started. The "
      "hypervolume's reference defaults to the front's nadir point (max f1, max f2).");

  m.def(
      "knee_index",
      [](const py::object& f1, const py::object& f2) -> py::object {
        const std::vector<ParetoPoint> points = points_of(f1, f2);
        if (nondominated(points).size() != points.size()) throw py::value_error("f1, f2: not a non-dominated front");
        for (std::size_t i = 1; i < points.size(); ++i) {
          if (!(points[i].f1 > points[i - 1].f1)) throw py::value_error("f1: a front must be sorted by f1 ascending");
        }
        const auto k = knee_index(points);
        return k ? py::object(py::int_(*k)) : py::object(py::none());
      },
      py::arg("f1"), py::arg("f2"), "Knee of a non-dominated front sorted by f1 (None: < 3 points or degenerate).");
  m.def(
      "hypervolume",
      [](const py::object& f1, const py::object& f2, const py::object& reference) {
        const Eigen::VectorXd r = vector_arg(reference, "reference", 2);
        return hypervolume(points_of(f1, f2), r(0), r(1));
      },
      py::arg("f1"), py::arg("f2"), py::arg("reference"), "Area dominated by the points up to reference (f1, f2).");
}

}  // namespace bivo::python
