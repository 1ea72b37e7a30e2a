// The conic IPM in Python: bivo.solve_conic(c, G, h, cones, A, b, ...) on numpy or
// scipy.sparse arrays (ECOS' argument convention: cones = {"l": orthant dim, "q": [SOC dims]}).
#include <sstream>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "python/bindings.h"
#include "solvers/conic/ipm_solver.h"

namespace bivo::python {
namespace {

using solvers::conic::ConeSpec;
using solvers::conic::ConicProblem;
using solvers::conic::IpmResult;
using solvers::conic::IpmSettings;
using solvers::conic::SparseMatrix;

// A dense 2-D array or any scipy.sparse matrix (converted to CSC), checked like every array.
SparseMatrix sparse_arg(const py::handle& value, const std::string& name, Eigen::Index rows, Eigen::Index cols) {
  if (py::hasattr(value, "tocsc")) {
    const py::object csc = value.attr("tocsc")();
    const py::tuple shape = csc.attr("shape");
    const auto r = shape[0].cast<Eigen::Index>(), c = shape[1].cast<Eigen::Index>();
    if (r != rows || c != cols) {
      std::ostringstream msg;
      msg << name << ": expected shape (" << rows << ", " << cols << "), got (" << r << ", " << c << ")";
      throw py::value_error(msg.str());
    }
    vector_arg(csc.attr("data"), name + " (nonzeros)");  // dtype and NaN/Inf checks
    csc.attr("sum_duplicates")();
    return csc.cast<SparseMatrix>();
  }
  return matrix_arg(value, name, rows, cols).sparseView(0.0, 0.0);
}

ConeSpec cones_arg(const py::dict& cones, Eigen::Index rows) {
  ConeSpec spec;
  for (const auto& item : cones) {
    const std::string key = py::str(item.first);
    if (key == "l") {
      spec.nonnegative = item.second.cast<int>();
    } else if (key == "q") {
      spec.soc = item.second.cast<std::vector<int>>();
    } else {
      throw py::value_error("cones: unknown key '" + key + "' (valid: 'l' orthant dimension, 'q' SOC dimensions)");
    }
  }
  if (spec.nonnegative < 0) throw py::value_error("cones: 'l' must be >= 0");
  long total = spec.nonnegative;
  for (int q : spec.soc) {
    if (q < 1) throw py::value_error("cones: every 'q' dimension must be >= 1, got " + std::to_string(q));
    total += q;
  }
  if (total != rows) {
    std::ostringstream msg;
    msg << "cones: dimensions sum to " << total << " but G and h have " << rows << " rows";
    throw py::value_error(msg.str());
  }
  return spec;
}

}  // namespace

void bind_conic(py::module_& m) {
  py::class_<IpmResult>(m, "ConicResult", "Result of bivo.solve_conic (solvers/conic/ipm_solver.h).")
      .def_property_readonly("status", [](const IpmResult& r) { return solvers::conic::to_string(r.status); })
      .def_property_readonly("status_text", [](const IpmResult& r) { return solvers::conic::status_text(r); })
      .def_readonly("x", &IpmResult::x)
      .def_readonly("y", &IpmResult::y)
      .def_readonly("z", &IpmResult::z)
      .def_readonly("s", &IpmResult::s)
      .def_readonly("primal_objective", &IpmResult::primal_objective)
      .def_readonly("dual_objective", &IpmResult::dual_objective)
      .def_readonly("primal_residual", &IpmResult::primal_residual)
      .def_readonly("dual_residual", &IpmResult::dual_residual)
      .def_readonly("gap", &IpmResult::gap)
      .def_readonly("relative_gap", &IpmResult::relative_gap)
      .def_readonly("objective_gap", &IpmResult::objective_gap)
      .def_readonly("infinite_rows", &IpmResult::infinite_rows)
      .def_readonly("reduced_accuracy", &IpmResult::reduced_accuracy)
      .def_readonly("polished", &IpmResult::polished)
      .def_readonly("note", &IpmResult::note)
      .def_readonly("iterations", &IpmResult::iterations)
      .def_readonly("seconds", &IpmResult::seconds)
      .def("__repr__", [](const IpmResult& r) { return "<ConicResult " + solvers::conic::status_text(r) + ">"; });

  m.def(
      "solve_conic",
      [](const py::object& c, const py::object& G, const py::object& h, const py::dict& cones, const py::object& A,
         const py::object& b, double feastol, double abstol, double reltol, int max_iterations,
         int equilibration_passes, bool polish, double gaptol, double infinity) {
        ConicProblem p;
        p.c = vector_arg(c, "c");
        const Eigen::Index n = p.c.size();
        p.h = vector_arg(h, "h");
        p.G = sparse_arg(G, "G", p.h.size(), n);
        p.cones = cones_arg(cones, p.h.size());
        if (A.is_none() != b.is_none()) throw py::value_error("A and b: give both or neither");
        if (!A.is_none()) {
          p.b = vector_arg(b, "b");
          p.A = sparse_arg(A, "A", p.b.size(), n);
        } else {
          p.A.resize(0, n);
          p.b.resize(0);
        }
        IpmSettings s;
        s.feastol = feastol;
        s.abstol = abstol;
        s.reltol = reltol;
        s.max_iterations = max_iterations;
        s.equilibration_passes = equilibration_passes;
        s.polish = polish;
        s.gaptol = gaptol;
        s.infinity = infinity;
        py::gil_scoped_release release;
        return solvers::conic::solve_conic(p, s);
      },
      py::arg("c"), py::arg("G"), py::arg("h"), py::arg("cones"), py::arg("A") = py::none(), py::arg("b") = py::none(),
      py::arg("feastol") = 1e-8, py::arg("abstol") = 1e-8, py::arg("reltol") = 1e-8, py::arg("max_iterations") = 100,
      py::arg("equilibration_passes") = 12, py::arg("polish") = true, py::arg("gaptol") = 1e-8,
      py::arg("infinity") = 1e20,
      "minimize c.x s.t. A x = b, G x + s = h, s in K = R^l_+ x Q^q1 x ...; G, A dense or scipy.sparse.");
}

}  // namespace bivo::python
