#include "solvers/conic/problem_data.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "solvers/error.h"

namespace bivo::solvers::conic {

namespace {

void check_finite(const Eigen::VectorXd& v, const char* what) {
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    if (!std::isfinite(v[i])) {
      throw Error(std::string("conic problem: ") + what + "[" + std::to_string(i) +
                  "] is not finite (" + std::to_string(v[i]) + ")");
    }
  }
}

void check_finite(const SparseMatrix& M, const char* what) {
  for (int j = 0; j < M.outerSize(); ++j) {
    for (SparseMatrix::InnerIterator it(M, j); it; ++it) {
      if (!std::isfinite(it.value())) {
        throw Error(std::string("conic problem: ") + what + "(" + std::to_string(it.row()) + ", " +
                    std::to_string(it.col()) + ") is not finite");
      }
    }
  }
}

std::string dims(const SparseMatrix& M) {
  return std::to_string(M.rows()) + " x " + std::to_string(M.cols());
}

}  // namespace

void validate(const ConicProblem& p) {
  const int n = p.num_variables();
  if (n == 0) throw Error("conic problem: no variables (c is empty)");
  if (p.A.cols() != n && !(p.A.rows() == 0 && p.A.cols() == 0)) {
    throw Error("conic problem: A is " + dims(p.A) + " but c has " + std::to_string(n) + " entries");
  }
  if (p.A.rows() != p.b.size()) {
    throw Error("conic problem: A has " + std::to_string(p.A.rows()) + " rows but b has " +
                std::to_string(p.b.size()) + " entries");
  }
  if (p.G.cols() != n && !(p.G.rows() == 0 && p.G.cols() == 0)) {
    throw Error("conic problem: G is " + dims(p.G) + " but c has " + std::to_string(n) + " entries");
  }
  if (p.G.rows() != p.h.size()) {
    throw Error("conic problem: G has " + std::to_string(p.G.rows()) + " rows but h has " +
                std::to_string(p.h.size()) + " entries");
  }
  if (p.cones.nonnegative < 0) throw Error("conic problem: negative orthant dimension");
  for (std::size_t k = 0; k < p.cones.soc.size(); ++k) {
    if (p.cones.soc[k] < 1) {
      throw Error("conic problem: second-order cone #" + std::to_string(k) + " has dimension " +
                  std::to_string(p.cones.soc[k]));
    }
  }
  if (p.cones.dim() != p.h.size()) {
    throw Error("conic problem: cone dimensions sum to " + std::to_string(p.cones.dim()) +
                " but G and h have " + std::to_string(p.h.size()) + " rows");
  }
  if (p.A.rows() > n) {
    throw Error("conic problem: more equality constraints (" + std::to_string(p.A.rows()) +
                ") than variables (" + std::to_string(n) + ")");
  }
  check_finite(p.c, "c");
  check_finite(p.b, "b");
  check_finite(p.h, "h");
  check_finite(p.A, "A");
  check_finite(p.G, "G");
}

Equilibration identity_equilibration(const ConicProblem& p) {
  return {Eigen::VectorXd::Ones(p.num_variables()), Eigen::VectorXd::Ones(p.num_equalities()),
          Eigen::VectorXd::Ones(p.num_cone_rows())};
}

Equilibration equilibrate(ConicProblem& p, int passes) {
  Equilibration e = identity_equilibration(p);
  const int n = p.num_variables(), me = p.num_equalities(), mc = p.num_cone_rows();
  // A scale of 0 (empty row/column) stays 1; each pass is bounded to avoid overflow on
  // pathological data.
  auto inv_sqrt = [](double v) { return v > 0.0 ? std::clamp(1.0 / std::sqrt(v), 1e-4, 1e4) : 1.0; };
  const ConeProduct cones(p.cones);
  Eigen::VectorXd col_max = Eigen::VectorXd::Zero(n), rowa = Eigen::VectorXd::Zero(me),
                  rowg = Eigen::VectorXd::Zero(mc);
  Eigen::VectorXd dc = Eigen::VectorXd::Ones(n), da = Eigen::VectorXd::Ones(me), dg = Eigen::VectorXd::Ones(mc);
  // One sweep over each matrix per pass: apply the previous pass's factors and take the
  // infinity norms of the result (the last sweep only applies).
  bool balanced = false;  // every factor of the last pass within 1 % of 1: stop early
  for (int pass = 0; pass <= passes; ++pass) {
    const bool last = pass == passes || balanced;
    col_max.setZero();
    rowa.setZero();
    rowg.setZero();
    auto sweep = [&](SparseMatrix& M, const Eigen::VectorXd& dr, Eigen::VectorXd& row_max) {
      for (int j = 0; j < M.outerSize(); ++j) {
        double cm = col_max[j];
        for (SparseMatrix::InnerIterator it(M, j); it; ++it) {
          const double v = it.valueRef() *= dr[it.row()] * dc[j];
          if (last) continue;
          const double a = std::abs(v);
          cm = std::max(cm, a);
          row_max[it.row()] = std::max(row_max[it.row()], a);
        }
        col_max[j] = cm;
      }
    };
    sweep(p.A, da, rowa);
    sweep(p.G, dg, rowg);
    p.c = p.c.cwiseProduct(dc);
    p.b = p.b.cwiseProduct(da);
    p.h = p.h.cwiseProduct(dg);
    e.col = e.col.cwiseProduct(dc);
    e.row_eq = e.row_eq.cwiseProduct(da);
    e.row_cone = e.row_cone.cwiseProduct(dg);
    if (last) break;
    // One factor per second-order cone: scaling rows of a cone differently would change K.
    for (int k = 0; k < cones.soc_count(); ++k) {
      const int o = cones.soc_offset(k), m = p.cones.soc[k];
      rowg.segment(o, m).setConstant(rowg.segment(o, m).maxCoeff());
    }
    for (int j = 0; j < n; ++j) dc[j] = inv_sqrt(col_max[j]);
    for (int i = 0; i < me; ++i) da[i] = inv_sqrt(rowa[i]);
    for (int i = 0; i < mc; ++i) dg[i] = inv_sqrt(rowg[i]);
    auto near_one = [](const Eigen::VectorXd& d) { return d.size() == 0 || (d.array() - 1.0).abs().maxCoeff() < 1e-2; };
    balanced = near_one(dc) && near_one(da) && near_one(dg);
  }
  return e;
}

}  // namespace bivo::solvers::conic
