// The JSON conic-program reader and the `bivo conic` result text (conic_file.h).
#include "experiments/conic_file.h"

#include <cstdio>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "solvers/error.h"

namespace bivo::experiments {

namespace {

using solvers::conic::ConicProblem;
using solvers::conic::SparseMatrix;
using json = nlohmann::json;

double number(const json& v, const std::string& where) {
  if (!v.is_number()) throw Error(where + " is not a number (" + v.dump() + ")");
  return v.get<double>();
}

Eigen::VectorXd vector_field(const json& doc, const char* key, const std::string& file, bool required) {
  if (!doc.contains(key)) {
    if (required) throw Error(file + ": missing \"" + key + "\"");
    return Eigen::VectorXd(0);
  }
  const json& a = doc.at(key);
  if (!a.is_array()) throw Error(file + ": \"" + key + "\" must be an array of numbers");
  Eigen::VectorXd v(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) v[i] = number(a[i], file + ": " + key + "[" + std::to_string(i) + "]");
  return v;
}

SparseMatrix matrix_field(const json& doc, const char* key, const std::string& file, int cols) {
  SparseMatrix M;
  if (!doc.contains(key)) {
    M.resize(0, cols);
    return M;
  }
  const json& a = doc.at(key);
  const std::string where = file + ": " + key;
  std::vector<Eigen::Triplet<double>> t;
  int rows = 0, ncols = cols;
  if (a.is_array()) {  // dense rows
    rows = static_cast<int>(a.size());
    for (int i = 0; i < rows; ++i) {
      if (!a[i].is_array() || static_cast<int>(a[i].size()) != cols) {
        throw Error(where + " row " + std::to_string(i) + " must have " + std::to_string(cols) +
                    " entries (the length of c)");
      }
      for (int j = 0; j < cols; ++j) {
        const double v = number(a[i][j], where + "[" + std::to_string(i) + "][" + std::to_string(j) + "]");
        if (v != 0.0) t.emplace_back(i, j, v);
      }
    }
  } else if (a.is_object()) {
    if (!a.contains("rows") || !a.contains("cols") || !a.contains("triplets")) {
      throw Error(where + " needs \"rows\", \"cols\" and \"triplets\"");
    }
    rows = static_cast<int>(number(a.at("rows"), where + ".rows"));
    ncols = static_cast<int>(number(a.at("cols"), where + ".cols"));
    if (rows < 0 || ncols != cols) {
      throw Error(where + " is " + std::to_string(rows) + " x " + std::to_string(ncols) + " but c has " +
                  std::to_string(cols) + " entries");
    }
    const json& tr = a.at("triplets");
    if (!tr.is_array()) throw Error(where + ".triplets must be an array of [i, j, v]");
    for (std::size_t k = 0; k < tr.size(); ++k) {
      const std::string w = where + ".triplets[" + std::to_string(k) + "]";
      if (!tr[k].is_array() || tr[k].size() != 3) throw Error(w + " must be [i, j, v]");
      const double fi = number(tr[k][0], w + "[0]"), fj = number(tr[k][1], w + "[1]");
      const int i = static_cast<int>(fi), j = static_cast<int>(fj);
      if (i != fi || j != fj || i < 0 || i >= rows || j < 0 || j >= cols) {
        throw Error(w + " index (" + tr[k][0].dump() + ", " + tr[k][1].dump() + ") outside " + std::to_string(rows) +
                    " x " + std::to_string(cols));
      }
      t.emplace_back(i, j, number(tr[k][2], w + "[2]"));
    }
  } else {
    throw Error(where + " must be dense rows or {rows, cols, triplets}");
  }
  M.resize(rows, cols);
  M.setFromTriplets(t.begin(), t.end());
  return M;
}

}  // namespace

ConicProblem read_conic_json(const std::string& file) {
  std::ifstream in(file);
  if (!in) throw Error("cannot open conic problem file '" + file + "'");
  json doc;
  try {
    in >> doc;
  } catch (const json::exception& e) {
    throw Error(file + ": not valid JSON (" + e.what() + ")");
  }
  if (!doc.is_object()) throw Error(file + ": top level must be an object");
  ConicProblem p;
  p.c = vector_field(doc, "c", file, true);
  const int n = static_cast<int>(p.c.size());
  p.A = matrix_field(doc, "A", file, n);
  p.b = vector_field(doc, "b", file, false);
  p.G = matrix_field(doc, "G", file, n);
  p.h = vector_field(doc, "h", file, false);
  if (!doc.contains("cones") || !doc.at("cones").is_object()) throw Error(file + ": missing \"cones\" object");
  const json& cones = doc.at("cones");
  if (cones.contains("l")) {
    const double l = number(cones.at("l"), file + ": cones.l");
    if (l < 0 || l != static_cast<int>(l)) throw Error(file + ": cones.l must be a non-negative integer, got " + cones.at("l").dump());
    p.cones.nonnegative = static_cast<int>(l);
  }
  if (cones.contains("q")) {
    if (!cones.at("q").is_array()) throw Error(file + ": cones.q must be an array of dimensions");
    for (std::size_t k = 0; k < cones.at("q").size(); ++k) {
      const double d = number(cones.at("q")[k], file + ": cones.q[" + std::to_string(k) + "]");
      if (d < 1 || d != static_cast<int>(d)) {
        throw Error(file + ": cones.q[" + std::to_string(k) + "] must be an integer >= 1, got " + cones.at("q")[k].dump());
      }
      p.cones.soc.push_back(static_cast<int>(d));
    }
  }
  try {
    solvers::conic::validate(p);
  } catch (const Error& e) {
    throw Error(file + ": " + e.what());
  }
  return p;
}

std::string conic_result_text(const solvers::conic::IpmResult& r, bool solution) {
  std::string out;
  char buf[256];
  auto line = [&](const char* fmt, auto... args) {
    std::snprintf(buf, sizeof buf, fmt, args...);
    out += buf;
  };
  line("status: %s%s\n", solvers::conic::to_string(r.status).c_str(), r.reduced_accuracy ? " (reduced accuracy)" : "");
  line("objective: %.12g (dual %.12g)\n", r.primal_objective, r.dual_objective);
  line("residuals: primal %.3e dual %.3e gap %.3e\n", r.primal_residual, r.dual_residual, r.gap);
  if (r.polished) {
    line("iterations: %d, then polished (%d Newton steps on the active set)\n", r.iterations, r.polish_newton_steps);
  } else {
    line("iterations: %d\n", r.iterations);
  }
  line("time: %.3f ms\n", 1e3 * r.seconds);
  if (solution) {
    auto print = [&](const char* name, const Eigen::VectorXd& v) {
      out += name;
      out += ":";
      for (Eigen::Index i = 0; i < v.size(); ++i) line(" %.12g", v[i]);
      out += "\n";
    };
    print("x", r.x);
    print("y", r.y);
    print("z", r.z);
    print("s", r.s);
  }
  return out;
}

}  // namespace bivo::experiments
