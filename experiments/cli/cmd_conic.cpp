// `bivo conic FILE`: solve a conic program (orthant x second-order cones) from a JSON file
// with the project's IPM. Format (docs/conic.md):
//   {"c": [..n..],
//    "A": <matrix p x n> (optional), "b": [..p..] (optional),
//    "G": <matrix m x n>, "h": [..m..],
//    "cones": {"l": <orthant dim>, "q": [<soc dims>...]}}
// <matrix> is either dense rows [[...], ...] or {"rows": r, "cols": c, "triplets": [[i, j, v], ...]}
// (0-based, duplicates summed).
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>

#include <nlohmann/json.hpp>

#include "experiments/cli/commands.h"
#include "solvers/conic/ipm_solver.h"
#include "solvers/error.h"

namespace bivo::experiments::cli {

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

ConicProblem read_problem(const std::string& file) {
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

}  // namespace

void add_conic_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("conic", "solve a conic program (orthant x SOC) from a JSON file with the own IPM");
  static std::string file;
  static solvers::conic::IpmSettings settings;
  static bool verbose = false, print_solution = false, no_polish = false;
  cmd->add_option("file", file, "JSON problem: c, A/b (optional), G, h, cones {l, q} (docs/conic.md)")->required();
  cmd->add_option("--feastol", settings.feastol, "primal/dual residual tolerance (relative)")->check(CLI::PositiveNumber);
  cmd->add_option("--abstol", settings.abstol, "absolute duality gap tolerance")->check(CLI::NonNegativeNumber);
  cmd->add_option("--reltol", settings.reltol, "relative duality gap tolerance")->check(CLI::PositiveNumber);
  cmd->add_option("--max-iter", settings.max_iterations, "iteration limit")->check(CLI::PositiveNumber);
  cmd->add_option("--equilibration-passes", settings.equilibration_passes, "Ruiz passes (0 = off)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag("--no-polish", no_polish, "interior-point iterations only, no active-set Newton polish");
  cmd->add_flag("--verbose,-v", verbose, "per-iteration log");
  cmd->add_flag("--solution", print_solution, "also print x, y, z, s");
  cmd->callback([] {
    const ConicProblem p = read_problem(file);
    if (verbose) settings.log = &std::cout;
    settings.polish = !no_polish;
    const auto r = solvers::conic::solve_conic(p, settings);
    std::printf("status: %s%s\n", solvers::conic::to_string(r.status).c_str(),
                r.reduced_accuracy ? " (reduced accuracy)" : "");
    std::printf("objective: %.12g (dual %.12g)\n", r.primal_objective, r.dual_objective);
    std::printf("residuals: primal %.3e dual %.3e gap %.3e\n", r.primal_residual, r.dual_residual, r.gap);
    if (r.polished) {
      std::printf("iterations: %d, then polished (%d Newton steps on the active set)\n", r.iterations,
                  r.polish_newton_steps);
    } else {
      std::printf("iterations: %d\n", r.iterations);
    }
    std::printf("time: %.3f ms\n", 1e3 * r.seconds);
    if (print_solution) {
      auto print = [](const char* name, const Eigen::VectorXd& v) {
        std::printf("%s:", name);
        for (Eigen::Index i = 0; i < v.size(); ++i) std::printf(" %.12g", v[i]);
        std::printf("\n");
      };
      print("x", r.x);
      print("y", r.y);
      print("z", r.z);
      print("s", r.s);
    }
  });
}

}  // namespace bivo::experiments::cli
