// The JSON conic-program reader and the `bivo conic` result text (conic_file.h).
#include "experiments/conic_files/conic_file.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include <nlohmann/json.hpp>

#include "odometry/io/json_file.h"
#include "solvers/error.h"

namespace bivo::experiments {

namespace {

using solvers::conic::ConicProblem;
using solvers::conic::SparseMatrix;
using json = nlohmann::json;

// Values are described, never serialised whole, so an error message stays short whatever
// the file holds (a dump of a deeply nested value would also recurse once per level).
std::string describe(const json& v) {
  switch (v.type()) {
    case json::value_t::array:
      return "an array of " + std::to_string(v.size()) + " entries";
    case json::value_t::object:
      return "an object of " + std::to_string(v.size()) + " keys";
    case json::value_t::string: {
      const auto& text = v.get_ref<const std::string&>();
      return "the string \"" + (text.size() > 40 ? text.substr(0, 40) + "..." : text) + "\"";
    }
    default:
      return v.dump();  // number, boolean, null: a few characters
  }
}

double number(const json& v, const std::string& where) {
  if (!v.is_number()) throw Error(where + " is not a number (" + describe(v) + ")");
  return v.get<double>();
}

// Every integer of the format (sizes, indices, cone dimensions) is range-checked here, in
// double, before any conversion: a cast of an out-of-range double to int is undefined.
int integer(const json& v, const std::string& where, int lo, int hi) {
  const double d = number(v, where);
  if (!(d >= lo && d <= hi) || d != std::floor(d)) {
    throw Error(where + " must be an integer in " + std::to_string(lo) + ".." + std::to_string(hi) + ", got " +
                describe(v));
  }
  return static_cast<int>(d);
}

constexpr int kMaxIndex = std::numeric_limits<int>::max();

// Array lengths become Eigen indices and row counts (int).
int length(const json& a, const std::string& where) {
  if (a.size() > static_cast<std::size_t>(kMaxIndex)) throw Error(where + " has more than 2^31 - 1 entries");
  return static_cast<int>(a.size());
}

Eigen::VectorXd vector_field(const json& doc, const char* key, const std::string& file, bool required) {
  if (!doc.contains(key)) {
    if (required) throw Error(file + ": missing \"" + key + "\"");
    return Eigen::VectorXd(0);
  }
  const json& a = doc.at(key);
  if (!a.is_array()) throw Error(file + ": \"" + key + "\" must be an array of numbers, got " + describe(a));
  const int size = length(a, file + ": " + key);
  Eigen::VectorXd v(size);
  for (int i = 0; i < size; ++i) v[i] = number(a[i], file + ": " + key + "[" + std::to_string(i) + "]");
  return v;
}

// `key`'s rows pair with the entries of the vector `paired` (A with b, G with h): a count that
// differs is refused before anything of that size is allocated (Eigen's setFromTriplets sorts
// through a transposed copy with one index per row).
SparseMatrix matrix_field(const json& doc, const char* key, const std::string& file, int cols, const char* paired,
                          int paired_rows) {
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
    rows = length(a, where);
    for (int i = 0; i < rows; ++i) {
      if (!a[i].is_array() || a[i].size() != static_cast<std::size_t>(cols)) {
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
    rows = integer(a.at("rows"), where + ".rows", 0, kMaxIndex);
    ncols = integer(a.at("cols"), where + ".cols", 0, kMaxIndex);
    if (ncols != cols) {
      throw Error(where + " is " + std::to_string(rows) + " x " + std::to_string(ncols) + " but c has " +
                  std::to_string(cols) + " entries");
    }
    const json& tr = a.at("triplets");
    if (!tr.is_array()) throw Error(where + ".triplets must be an array of [i, j, v]");
    for (std::size_t k = 0; k < tr.size(); ++k) {
      const std::string w = where + ".triplets[" + std::to_string(k) + "]";
      if (!tr[k].is_array() || tr[k].size() != 3) throw Error(w + " must be [i, j, v]");
      const int i = integer(tr[k][0], w + "[0]", 0, kMaxIndex), j = integer(tr[k][1], w + "[1]", 0, kMaxIndex);
      if (i >= rows || j >= cols) {
        throw Error(w + " index (" + std::to_string(i) + ", " + std::to_string(j) + ") outside " +
                    std::to_string(rows) + " x " + std::to_string(cols));
      }
      t.emplace_back(i, j, number(tr[k][2], w + "[2]"));
    }
  } else {
    throw Error(where + " must be dense rows or {rows, cols, triplets}, got " + describe(a));
  }
  if (rows != paired_rows) {
    throw Error(where + " has " + std::to_string(rows) + " rows but " + paired + " has " + std::to_string(paired_rows) +
                " entries");
  }
  M.resize(rows, cols);
  M.setFromTriplets(t.begin(), t.end());
  return M;
}

}  // namespace

ConicProblem read_conic_json(const std::string& file) {
  // The format nests three levels deep; far deeper input is refused while it is read.
  const json doc = odometry::io::read_json_file(file, "conic problem file", 16);
  if (!doc.is_object()) throw Error(file + ": top level must be an object");
  ConicProblem p;
  p.c = vector_field(doc, "c", file, true);
  const int n = static_cast<int>(p.c.size());
  p.b = vector_field(doc, "b", file, false);
  p.A = matrix_field(doc, "A", file, n, "b", static_cast<int>(p.b.size()));
  p.h = vector_field(doc, "h", file, false);
  p.G = matrix_field(doc, "G", file, n, "h", static_cast<int>(p.h.size()));
  if (!doc.contains("cones") || !doc.at("cones").is_object()) throw Error(file + ": missing \"cones\" object");
  const json& cones = doc.at("cones");
  if (cones.contains("l")) p.cones.nonnegative = integer(cones.at("l"), file + ": cones.l", 0, kMaxIndex);
  if (cones.contains("q")) {
    const json& q = cones.at("q");
    if (!q.is_array()) throw Error(file + ": cones.q must be an array of dimensions, got " + describe(q));
    for (int k = 0; k < length(q, file + ": cones.q"); ++k) {
      p.cones.soc.push_back(integer(q[k], file + ": cones.q[" + std::to_string(k) + "]", 1, kMaxIndex));
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
  line("residuals: primal %.3e dual %.3e gap %.3e objective gap %.3e\n", r.primal_residual, r.dual_residual, r.gap,
       r.objective_gap);
  if (r.infinite_rows > 0)
    line("infinite bounds: %d rows removed before the solve (z = 0, s = h - G x there)\n", r.infinite_rows);
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
