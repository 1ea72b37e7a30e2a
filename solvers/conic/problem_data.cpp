#include "solvers/conic/problem_data.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "solvers/conic/dense_kernels.h"
#include "solvers/error.h"

namespace bivo::solvers::conic {

namespace {

void check_finite(const Eigen::VectorXd& v, const char* what) {
  if (kernels::all_finite(v.size(), v.data())) return;  // the common case, vectorized
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    if (!std::isfinite(v[i])) {
      throw Error(std::string("conic problem: ") + what + "[" + std::to_string(i) + "] is not finite (" +
                  std::to_string(v[i]) + ")");
    }
  }
}

void check_finite(const SparseMatrix& M, const char* what) {
  if (M.isCompressed() && kernels::all_finite(M.nonZeros(), M.valuePtr())) return;
  for (int j = 0; j < M.outerSize(); ++j) {
    for (SparseMatrix::InnerIterator it(M, j); it; ++it) {
      if (!std::isfinite(it.value())) {
        throw Error(std::string("conic problem: ") + what + "(" + std::to_string(it.row()) + ", " +
                    std::to_string(it.col()) + ") is not finite");
      }
    }
  }
}

std::string dims(const SparseMatrix& M) { return std::to_string(M.rows()) + " x " + std::to_string(M.cols()); }

}  // namespace

void validate(const ConicProblem& p) {
  const int n = p.num_variables();
  if (n == 0) throw Error("conic problem: no variables (c is empty)");
  if (p.A.cols() != n && !(p.A.rows() == 0 && p.A.cols() == 0)) {
    throw Error("conic problem: A is " + dims(p.A) + " but c has " + std::to_string(n) + " entries");
  }
  if (p.A.rows() != p.b.size()) {
    throw Error("conic problem: A has " + std::to_string(p.A.rows()) + " rows but b has " + std::to_string(p.b.size()) +
                " entries");
  }
  if (p.has_dense_G()) {
    if (p.G.rows() != 0 || p.G.cols() != 0) throw Error("conic problem: both a sparse and a dense G");
    if (p.dense_G.cols() != n || p.dense_G.rows() != p.h.size()) {
      throw Error("conic problem: dense G is " + std::to_string(p.dense_G.rows()) + " x " +
                  std::to_string(p.dense_G.cols()) + " but c has " + std::to_string(n) + " entries and h " +
                  std::to_string(p.h.size()));
    }
  } else if (p.G.cols() != n && !(p.G.rows() == 0 && p.G.cols() == 0)) {
    throw Error("conic problem: G is " + dims(p.G) + " but c has " + std::to_string(n) + " entries");
  }
  if (!p.has_dense_G() && p.G.rows() != p.h.size()) {
    throw Error("conic problem: G has " + std::to_string(p.G.rows()) + " rows but h has " + std::to_string(p.h.size()) +
                " entries");
  }
  if (p.cones.nonnegative < 0) throw Error("conic problem: negative orthant dimension");
  for (std::size_t k = 0; k < p.cones.soc.size(); ++k) {
    if (p.cones.soc[k] < 1) {
      throw Error("conic problem: second-order cone #" + std::to_string(k) + " has dimension " +
                  std::to_string(p.cones.soc[k]));
    }
  }
  if (p.cones.dim() != p.h.size()) {
    throw Error("conic problem: cone dimensions sum to " + std::to_string(p.cones.dim()) + " but G and h have " +
                std::to_string(p.h.size()) + " rows");
  }
  if (p.A.rows() > n) {
    throw Error("conic problem: more equality constraints (" + std::to_string(p.A.rows()) + ") than variables (" +
                std::to_string(n) + ")");
  }
  check_finite(p.c, "c");
  check_finite(p.b, "b");
  check_finite(p.h, "h");
  check_finite(p.A, "A");
  check_finite(p.G, "G");
  if (p.has_dense_G() && !kernels::all_finite(p.dense_G.size(), p.dense_G.data())) {
    for (Eigen::Index j = 0; j < p.dense_G.cols(); ++j) {
      for (Eigen::Index i = 0; i < p.dense_G.rows(); ++i) {
        if (!std::isfinite(p.dense_G(i, j))) {
          throw Error("conic problem: G(" + std::to_string(i) + ", " + std::to_string(j) + ") is not finite");
        }
      }
    }
  }
}

Equilibration identity_equilibration(const ConicProblem& p) {
  return {Eigen::VectorXd::Ones(p.num_variables()), Eigen::VectorXd::Ones(p.num_equalities()),
          Eigen::VectorXd::Ones(p.num_cone_rows())};
}

Equilibration equilibration_factors(const ConicProblem& p, int passes) {
  Equilibration e;
  equilibration_factors(p, passes, e);
  return e;
}

void equilibration_factors(const ConicProblem& p, int passes, Equilibration& e) {
  const int n = p.num_variables(), me = p.num_equalities(), l = p.cones.nonnegative;
  const int nsoc = static_cast<int>(p.cones.soc.size());
  e.col.setOnes(n);
  e.row_eq.setOnes(me);
  e.row_cone.setOnes(p.num_cone_rows());
  if (passes <= 0) return;
  // Blocks: the equality rows, then one per orthant row, then one per second-order cone.
  // soc_end[k]: one past cone k's last row (the cones' rows are contiguous, in order).
  std::vector<int> soc_end(nsoc);
  for (int k = 0, end = l; k < nsoc; ++k) soc_end[k] = end += p.cones.soc[k];
  const int nb = me + l + nsoc;
  // Block maxima by columns (a cone's rows are contiguous and sorted within a column of G,
  // so a block is one run of entries; its max is a tight loop over the values).
  std::vector<int> start(n + 1, 0), block;
  std::vector<double> bmax;
  for (int j = 0; j < n; ++j) {
    if (j < p.A.outerSize()) {
      for (SparseMatrix::InnerIterator it(p.A, j); it; ++it) {
        block.push_back(static_cast<int>(it.row()));
        bmax.push_back(std::abs(it.value()));
      }
    }
    if (j < p.G.outerSize()) {
      const int* inner = p.G.innerIndexPtr();
      const double* val = p.G.valuePtr();
      const int begin = p.G.outerIndexPtr()[j];
      const int end = p.G.isCompressed() ? p.G.outerIndexPtr()[j + 1] : begin + p.G.innerNonZeroPtr()[j];
      for (int q = begin; q < end;) {
        const int row = inner[q];
        int b, last;
        if (row < l) {
          b = me + row;
          last = row + 1;
        } else {
          const int k = static_cast<int>(std::upper_bound(soc_end.begin(), soc_end.end(), row) - soc_end.begin());
          b = me + l + k;
          last = soc_end[k];
        }
        const int run_end = static_cast<int>(std::lower_bound(inner + q, inner + end, last) - inner);
        block.push_back(b);
        bmax.push_back(kernels::max_abs(run_end - q, val + q));
        q = run_end;
      }
    }
    if (p.has_dense_G()) {  // one run per block of the column
      const double* col = p.dense_G.col(j).data();
      for (int i = 0; i < l; ++i) {
        block.push_back(me + i);
        bmax.push_back(std::abs(col[i]));
      }
      for (int k = 0, begin = l; k < nsoc; begin = soc_end[k++]) {
        block.push_back(me + l + k);
        bmax.push_back(kernels::max_abs(soc_end[k] - begin, col + begin));
      }
    }
    start[j + 1] = static_cast<int>(block.size());
  }
  // A scale of 0 (empty row/column) stays 1; each pass is bounded to avoid overflow on
  // pathological data.
  auto inv_sqrt = [](double v) { return v > 0.0 ? std::clamp(1.0 / std::sqrt(v), 1e-4, 1e4) : 1.0; };
  std::vector<double> col(n, 1.0), row(nb, 1.0), col_max(n), row_max(nb);
  for (int pass = 0; pass < passes; ++pass) {
    std::fill(row_max.begin(), row_max.end(), 0.0);
    for (int j = 0; j < n; ++j) {
      double cm = 0.0;
      for (int q = start[j]; q < start[j + 1]; ++q) {
        const double a = bmax[q] * row[block[q]] * col[j];
        cm = std::max(cm, a);
        row_max[block[q]] = std::max(row_max[block[q]], a);
      }
      col_max[j] = cm;
    }
    bool balanced = true;  // every factor of this pass within 1 % of 1: stop
    for (int j = 0; j < n; ++j) {
      const double f = inv_sqrt(col_max[j]);
      balanced = balanced && std::abs(f - 1.0) < 1e-2;
      col[j] *= f;
    }
    for (int b = 0; b < nb; ++b) {
      const double f = inv_sqrt(row_max[b]);
      balanced = balanced && std::abs(f - 1.0) < 1e-2;
      row[b] *= f;
    }
    if (balanced) break;
  }
  for (int j = 0; j < n; ++j) e.col[j] = col[j];
  for (int i = 0; i < me; ++i) e.row_eq[i] = row[i];
  for (int i = 0; i < l; ++i) e.row_cone[i] = row[me + i];
  for (int k = 0, begin = l; k < nsoc; begin = soc_end[k++]) {
    e.row_cone.segment(begin, soc_end[k] - begin).setConstant(row[me + l + k]);
  }
}

void scale_vectors_and_equalities(ConicProblem& p, const Equilibration& e) {
  p.c = p.c.cwiseProduct(e.col);
  p.b = p.b.cwiseProduct(e.row_eq);
  p.h = p.h.cwiseProduct(e.row_cone);
  for (int j = 0; j < p.A.outerSize(); ++j) {
    for (SparseMatrix::InnerIterator it(p.A, j); it; ++it) it.valueRef() *= e.row_eq[it.row()] * e.col[j];
  }
}

Equilibration equilibrate(ConicProblem& p, int passes) {
  const Equilibration e = equilibration_factors(p, passes);
  scale_vectors_and_equalities(p, e);
  if (p.has_dense_G()) p.dense_G = e.row_cone.asDiagonal() * p.dense_G * e.col.asDiagonal();
  for (int j = 0; j < p.G.outerSize(); ++j) {
    for (SparseMatrix::InnerIterator it(p.G, j); it; ++it) it.valueRef() *= e.row_cone[it.row()] * e.col[j];
  }
  return e;
}

}  // namespace bivo::solvers::conic
