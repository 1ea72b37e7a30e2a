#include "solvers/conic/residuals.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace bivo::solvers::conic {

void compute_residuals(const ConicProblem& sp, const ConstraintMatrix& G, const ConicProblem& op,
                       const Equilibration& eq, const Variables& v, Residuals& r) {
  const int p = sp.num_equalities(), m = sp.num_cone_rows();
  Eigen::VectorXd& atyz = r.atyz;  // A^T y + G^T z (scaled)
  Eigen::VectorXd& ax = r.ax;
  Eigen::VectorXd& gx = r.gx;
  atyz.setZero(sp.num_variables());
  ax.setZero(p);
  gx.setZero(m);
  if (p > 0) {
    atyz.noalias() += sp.A.transpose() * v.y;
    ax.noalias() = sp.A * v.x;
  }
  if (m > 0) {
    G.add_multiply_transpose(1.0, v.z, atyz);
    G.multiply(v.x, gx);
  }
  r.rx.noalias() = -(atyz + sp.c * v.tau);
  r.ry.noalias() = ax - sp.b * v.tau;
  r.rz.noalias() = v.s + gx - sp.h * v.tau;
  const double cx = sp.c.dot(v.x), by = sp.b.dot(v.y), hz = sp.h.dot(v.z);
  r.rtau = v.kappa + cx + by + hz;

  // Back to original units: dual-space rows by 1/D, primal equality rows by 1/Ea, cone rows by 1/Eg.
  const auto atyz_o = atyz.cwiseQuotient(eq.col);
  const auto ax_o = ax.cwiseQuotient(eq.row_eq);
  const auto gxs_o = (gx + v.s).cwiseQuotient(eq.row_cone);
  const double tau = v.tau;
  const double nb = std::max(1.0, op.b.norm()), nh = std::max(1.0, op.h.norm()), nc = std::max(1.0, op.c.norm());
  r.primal_residual =
      std::max(p > 0 ? (ax_o / tau - op.b).norm() / nb : 0.0, m > 0 ? (gxs_o / tau - op.h).norm() / nh : 0.0);
  // Block by block too (certificate.h): the same measure the returned point is certified on.
  if (p > 0) {
    r.primal_residual = std::max(
        r.primal_residual, blockwise_residual(nullptr, p, ax.data(), nullptr, op.b.data(), eq.row_eq.data(), tau));
  }
  if (m > 0) {
    r.gxs = gx + v.s;
    r.primal_residual = std::max(r.primal_residual, blockwise_residual(&op.cones, m, r.gxs.data(), v.s.data(),
                                                                       op.h.data(), eq.row_cone.data(), tau));
  }
  r.dual_residual = (atyz_o / tau + op.c).norm() / nc;
  // Scaling leaves c^T x, b^T y, h^T z and s^T z unchanged.
  r.primal_objective = cx / tau;
  r.dual_objective = -(by + hz) / tau;
  r.gap = v.s.dot(v.z) / (tau * tau);
  if (r.primal_objective < 0.0) {
    r.relative_gap = r.gap / -r.primal_objective;
  } else if (r.dual_objective > 0.0) {
    r.relative_gap = r.gap / r.dual_objective;
  } else {
    r.relative_gap = std::numeric_limits<double>::infinity();
  }
  r.objective_gap = std::abs(cx + by + hz) / tau / (1.0 + std::abs(r.primal_objective));
  r.hz_by = hz + by;
  r.primal_infeasibility = r.hz_by < 0.0 ? atyz_o.norm() / -r.hz_by : std::numeric_limits<double>::infinity();
  r.cx = cx;
  r.dual_infeasibility = cx < 0.0 ? std::max(ax_o.norm(), gxs_o.norm()) / -cx : std::numeric_limits<double>::infinity();
}

ResidualFloors residual_floors(const ConicProblem& sp, const ConstraintMatrix& G, const ConicProblem& op,
                               const Equilibration& eq, const Variables& v) {
  ResidualFloors f;
  const int n = sp.num_variables(), p = sp.num_equalities(), m = sp.num_cone_rows();
  if (!(v.tau > 0.0)) return f;
  const double eps = std::numeric_limits<double>::epsilon();
  // Dual: |A|^T |y| + |G|^T |z| + |c| tau, per column; terms per column ~ p + m.
  Eigen::VectorXd dual = sp.c.cwiseAbs() * v.tau;
  if (p > 0) dual.noalias() += sp.A.cwiseAbs().transpose() * v.y.cwiseAbs();
  Eigen::VectorXd primal_g = v.s.cwiseAbs() + sp.h.cwiseAbs() * v.tau;
  if (m > 0) {
    const Eigen::VectorXd az = v.z.cwiseAbs(), ax = v.x.cwiseAbs();
    if (G.dense()) {
      dual.noalias() += G.dense_matrix().cwiseAbs().transpose() * az;
      primal_g.noalias() += G.dense_matrix().cwiseAbs() * ax;
    } else {
      dual.noalias() += G.sparse().cwiseAbs().transpose() * az;
      primal_g.noalias() += G.by_rows().cwiseAbs() * ax;
    }
  }
  const double nb = std::max(1.0, op.b.norm()), nh = std::max(1.0, op.h.norm()), nc = std::max(1.0, op.c.norm());
  f.dual = eps * std::sqrt(static_cast<double>(p + m + 1)) * dual.cwiseQuotient(eq.col).norm() / v.tau / nc;
  double pa = 0.0;
  if (p > 0) {
    const Eigen::VectorXd primal_a = sp.A.cwiseAbs() * v.x.cwiseAbs() + sp.b.cwiseAbs() * v.tau;
    pa = eps * std::sqrt(static_cast<double>(n + 1)) * primal_a.cwiseQuotient(eq.row_eq).norm() / v.tau / nb;
  }
  const double pg =
      m > 0 ? eps * std::sqrt(static_cast<double>(n + 2)) * primal_g.cwiseQuotient(eq.row_cone).norm() / v.tau / nh
            : 0.0;
  f.primal = std::max(pa, pg);
  return f;
}

}  // namespace bivo::solvers::conic
