#include "solvers/conic/certificate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "solvers/conic/cones.h"

namespace bivo::solvers::conic {

Tolerances strict_tolerances(const IpmSettings& s) { return {s.feastol, s.abstol, s.reltol, s.gaptol}; }

Tolerances reduced_tolerances(const IpmSettings& s) {
  // Never stricter than the strict ones (a caller may loosen those past the defaults).
  return {std::max(s.feastol, s.feastol_inaccurate), std::max(s.abstol, s.abstol_inaccurate),
          std::max(s.reltol, s.reltol_inaccurate), std::max(s.gaptol, s.gaptol_inaccurate)};
}

IpmStatus verdict(const ExitMeasures& m, const Tolerances& t) {
  const bool in_cone = m.cone_violation <= t.feastol;
  if (in_cone && m.primal_residual < t.feastol && m.dual_residual < t.feastol &&
      (m.gap < t.abstol || m.relative_gap < t.reltol) && m.objective_gap < t.gaptol) {
    return IpmStatus::kOptimal;
  }
  if (in_cone && m.hz_by < 0.0 && m.primal_infeasibility < t.feastol) return IpmStatus::kPrimalInfeasible;
  if (in_cone && m.cx < 0.0 && m.dual_infeasibility < t.feastol) return IpmStatus::kDualInfeasible;
  return IpmStatus::kMaxIterations;
}

double blockwise_residual(const ConeSpec* cones, int rows, const double* gxs, const double* s, const double* h,
                          const double* scale, double tau) {
  double worst = 0.0;
  // One factor per block: the equilibration keeps a single row scale per second-order cone,
  // so the paper's cones of 1e5 rows cost no division per row.
  auto block = [&](int begin, int end) {
    const double f = 1.0 / ((scale ? scale[begin] : 1.0) * tau);
    double r2 = 0.0, h2 = 0.0, s2 = 0.0;
    for (int i = begin; i < end; ++i) {
      const double r = gxs[i] * f - h[i];
      r2 += r * r;
      h2 += h[i] * h[i];
      if (s) s2 += s[i] * s[i];
    }
    worst = std::max(worst, std::sqrt(r2) / (1.0 + std::sqrt(h2) + f * std::sqrt(s2)));
  };
  const int l = cones ? cones->nonnegative : rows;
  for (int i = 0; i < l; ++i) block(i, i + 1);
  if (cones) {
    int offset = l;
    for (const int d : cones->soc) {
      block(offset, offset + d);
      offset += d;
    }
  }
  return std::isnan(worst) ? std::numeric_limits<double>::infinity() : worst;
}

namespace {

double cone_violation(const ConeProduct& K, const Eigen::VectorXd& u) {
  if (u.size() == 0) return 0.0;
  const double e = K.min_eigenvalue(u);
  return e >= 0.0 ? 0.0 : -e / (1.0 + u.cwiseAbs().maxCoeff());
}

}  // namespace

ExitMeasures measure_point(const ConicProblem& p, const Eigen::VectorXd& x, const Eigen::VectorXd& y,
                           const Eigen::VectorXd& z, const Eigen::VectorXd& s) {
  ExitMeasures m;
  const int n = p.num_variables(), np = p.num_equalities(), nm = p.num_cone_rows();
  const auto inf = std::numeric_limits<double>::infinity();
  if (x.size() != n || y.size() != np || z.size() != nm || s.size() != nm) {
    m.primal_residual = m.dual_residual = m.objective_gap = m.gap = m.relative_gap = inf;
    m.primal_infeasibility = m.dual_infeasibility = inf;
    return m;
  }
  Eigen::VectorXd aty = Eigen::VectorXd::Zero(n), gtz = Eigen::VectorXd::Zero(n);
  Eigen::VectorXd ax = Eigen::VectorXd::Zero(np), gx = Eigen::VectorXd::Zero(nm);
  if (np > 0) {
    aty.noalias() = p.A.transpose() * y;
    ax.noalias() = p.A * x;
  }
  if (nm > 0) {
    if (p.has_dense_G()) {
      gtz.noalias() = p.dense_G.transpose() * z;
      gx.noalias() = p.dense_G * x;
    } else if (p.G.cols() == n) {
      gtz.noalias() = p.G.transpose() * z;
      gx.noalias() = p.G * x;
    }
  }
  const double nb = std::max(1.0, p.b.norm()), nh = std::max(1.0, p.h.norm()), nc = std::max(1.0, p.c.norm());
  m.primal_residual = std::max(np > 0 ? (ax - p.b).norm() / nb : 0.0, nm > 0 ? (gx + s - p.h).norm() / nh : 0.0);
  if (np > 0)
    m.primal_residual =
        std::max(m.primal_residual, blockwise_residual(nullptr, np, ax.data(), nullptr, p.b.data(), nullptr, 1.0));
  if (nm > 0) {
    const Eigen::VectorXd gxs = gx + s;
    m.primal_residual =
        std::max(m.primal_residual, blockwise_residual(&p.cones, nm, gxs.data(), s.data(), p.h.data(), nullptr, 1.0));
  }
  m.dual_residual = (aty + gtz + p.c).norm() / nc;
  const double cx = p.c.dot(x), by = np > 0 ? p.b.dot(y) : 0.0, hz = nm > 0 ? p.h.dot(z) : 0.0;
  m.primal_objective = cx;
  m.dual_objective = -(by + hz);
  m.gap = nm > 0 ? s.dot(z) : 0.0;
  if (m.primal_objective < 0.0) {
    m.relative_gap = m.gap / -m.primal_objective;
  } else if (m.dual_objective > 0.0) {
    m.relative_gap = m.gap / m.dual_objective;
  } else {
    m.relative_gap = inf;
  }
  m.objective_gap = std::abs(cx + by + hz) / (1.0 + std::abs(cx));
  const ConeProduct K(p.cones);
  m.cone_violation = std::max(cone_violation(K, s), cone_violation(K, z));
  m.hz_by = hz + by;
  m.primal_infeasibility = m.hz_by < 0.0 ? (aty + gtz).norm() / -m.hz_by : inf;
  m.cx = cx;
  m.dual_infeasibility = cx < 0.0 ? std::max(ax.norm(), (gx + s).norm()) / -cx : inf;
  if (!std::isfinite(m.primal_residual) || !std::isfinite(m.dual_residual)) m.primal_residual = m.dual_residual = inf;
  return m;
}

std::string shortfall(const ExitMeasures& m, IpmStatus claim, const Tolerances& t, double primal_floor,
                      double dual_floor) {
  char buf[220];
  std::string why;
  auto add = [&](const char* what, double value, double tol, double floor) {
    if (value < tol) return;
    std::snprintf(buf, sizeof buf, "%s%s %.1e > %.1e", why.empty() ? "" : ", ", what, value, tol);
    why += buf;
    if (floor > 0.0 && tol < floor) {
      std::snprintf(buf, sizeof buf, " (below its rounding floor %.1e)", floor);
      why += buf;
    }
  };
  if (m.cone_violation > t.feastol) add("cone violation", m.cone_violation, t.feastol, 0.0);
  if (claim == IpmStatus::kPrimalInfeasible) {
    if (!(m.hz_by < 0.0)) why += std::string(why.empty() ? "" : ", ") + "h'z + b'y >= 0";
    add("infeasibility residual ||A'y + G'z||", m.primal_infeasibility, t.feastol, 0.0);
    return why;
  }
  if (claim == IpmStatus::kDualInfeasible) {
    if (!(m.cx < 0.0)) why += std::string(why.empty() ? "" : ", ") + "c'x >= 0";
    add("unboundedness residual max(||Ax||, ||Gx + s||)", m.dual_infeasibility, t.feastol, 0.0);
    return why;
  }
  add("primal residual", m.primal_residual, t.feastol, primal_floor);
  add("dual residual", m.dual_residual, t.feastol, dual_floor);
  if (!(m.gap < t.abstol || m.relative_gap < t.reltol)) {
    std::snprintf(buf, sizeof buf, "%sgap s'z %.1e (relative %.1e) above abstol %.1e / reltol %.1e",
                  why.empty() ? "" : ", ", m.gap, m.relative_gap, t.abstol, t.reltol);
    why += buf;
  }
  add("objective gap |c'x + b'y + h'z| / (1 + |c'x|)", m.objective_gap, t.gaptol, 0.0);
  return why;
}

ExitMeasures certify(const ConicProblem& problem, const IpmSettings& settings, IpmResult& r) {
  const ExitMeasures m = measure_point(problem, r.x, r.y, r.z, r.s);
  r.primal_objective = m.primal_objective;
  r.dual_objective = m.dual_objective;
  r.primal_residual = m.primal_residual;
  r.dual_residual = m.dual_residual;
  r.gap = m.gap;
  r.relative_gap = m.relative_gap;
  r.objective_gap = m.objective_gap;
  r.reduced_accuracy = false;
  const IpmStatus claim = r.status;
  if (claim != IpmStatus::kOptimal && claim != IpmStatus::kPrimalInfeasible && claim != IpmStatus::kDualInfeasible) {
    return m;
  }
  const Tolerances strict = strict_tolerances(settings);
  if (verdict(m, strict) == claim) {
    r.note.clear();
    return m;
  }
  if (verdict(m, reduced_tolerances(settings)) == claim) {
    r.reduced_accuracy = true;
    r.note = shortfall(m, claim, strict, r.primal_residual_floor, r.dual_residual_floor);
    return m;
  }
  r.status = IpmStatus::kNumericalTrouble;
  r.note = "the returned point fails the " + to_string(claim) +
           " certificate on the given data: " + shortfall(m, claim, reduced_tolerances(settings));
  return m;
}

}  // namespace bivo::solvers::conic
