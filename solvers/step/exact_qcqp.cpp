// The exact one-constraint QCQP step (eq. `QCQP`); the math is in docs/solvers.md.
#include "solvers/step/exact_qcqp.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "solvers/error.h"
#include "solvers/scalarization.h"

namespace bivo::solvers {
namespace {

struct ReducedModel {
  Eigen::MatrixXd H;
  Eigen::VectorXd b;
  double a = 0.0;
  double value(const Eigen::VectorXd& d) const { return a + 2.0 * b.dot(d) + d.dot(H * d); }
};

// LDL^T pivots all well above zero (relative to the largest) and a good condition estimate;
// anything doubtful goes through the eigendecomposition paths, which handle rank exactly.
bool safely_positive_definite(const Eigen::LDLT<Eigen::MatrixXd>& ldlt, double tol) {
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return false;
  const Eigen::VectorXd D = ldlt.vectorD();
  return D.minCoeff() > 1e3 * tol * D.cwiseAbs().maxCoeff() && ldlt.rcond() > 10.0 * tol;
}

// argmin mA, ties broken by mB (the limit of argmin mA + t mB as t -> 0+). Requires
// HA + HB positive definite, which the reduction below guarantees.
Eigen::VectorXd lexicographic_minimizer(const ReducedModel& A, const ReducedModel& B, double tol) {
  {
    // Common case: HA safely nonsingular, its minimizer is unique.
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(A.H);
    if (safely_positive_definite(ldlt, tol)) return ldlt.solve(-A.b);
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(A.H);
  const Eigen::VectorXd& s = eig.eigenvalues();
  const Eigen::MatrixXd& V = eig.eigenvectors();
  const double cut = tol * std::max(s.cwiseAbs().maxCoeff(), std::numeric_limits<double>::min());
  const Eigen::Index n = s.size();
  Eigen::VectorXd c = -(V.transpose() * A.b);
  std::vector<Eigen::Index> null_idx;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (s(i) > cut) {
      c(i) /= s(i);
    } else {
      c(i) = 0.0;
      null_idx.push_back(i);
    }
  }
  Eigen::VectorXd d = V * c;  // minimum-norm minimizer of mA
  if (!null_idx.empty()) {
    Eigen::MatrixXd Z(n, static_cast<Eigen::Index>(null_idx.size()));
    for (std::size_t k = 0; k < null_idx.size(); ++k) Z.col(static_cast<Eigen::Index>(k)) = V.col(null_idx[k]);
    // Among d + Z z (all minimizers of mA) minimize mB: (Z^T HB Z) z = -Z^T (HB d + bB).
    const Eigen::MatrixXd M = Z.transpose() * B.H * Z;
    const Eigen::VectorXd rhs = -(Z.transpose() * (B.H * d + B.b));
    d += Z * M.ldlt().solve(rhs);
  }
  return d;
}

}  // namespace

ExactQcqpResult solve_qcqp_exact(const QuadraticModel& m1, const QuadraticModel& m2, double epsilon,
                                 const ExactQcqpOptions& options) {
  if (!std::isfinite(epsilon) || epsilon < 0.0) {
    std::ostringstream msg;
    msg << "exact QCQP step: epsilon must be finite and >= 0, got " << epsilon;
    throw Error(msg.str());
  }
  Linearization check;
  check.f1 = m1;
  check.f2 = m2;
  validate_linearization(check);
  const Eigen::Index n = m1.b.size();

  // Project out the common null space of H_1 and H_2 (each scaled by its trace so that very
  // different units, intensity vs depth, do not hide one of them).
  const Eigen::MatrixXd H1 = 0.5 * (m1.H + m1.H.transpose());
  const Eigen::MatrixXd H2 = 0.5 * (m2.H + m2.H.transpose());
  const double t1 = H1.trace(), t2 = H2.trace();
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(n, n);
  if (t1 > 0.0) S += H1 / t1;
  if (t2 > 0.0) S += H2 / t2;
  Eigen::MatrixXd Q;  // orthonormal basis of range(S); identity when S is nonsingular
  const Eigen::LDLT<Eigen::MatrixXd> s_ldlt(S);
  if (safely_positive_definite(s_ldlt, options.rank_tolerance)) {
    Q = Eigen::MatrixXd::Identity(n, n);  // fast path: no common null space
  } else {
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(S);
    const double smax = eig.eigenvalues().cwiseAbs().maxCoeff();
    std::vector<Eigen::Index> keep;
    for (Eigen::Index i = 0; i < n; ++i) {
      if (eig.eigenvalues()(i) > options.rank_tolerance * smax && eig.eigenvalues()(i) > 0.0) keep.push_back(i);
    }
    if (static_cast<Eigen::Index>(keep.size()) == n) {
      Q = Eigen::MatrixXd::Identity(n, n);
    } else {
      Q.resize(n, static_cast<Eigen::Index>(keep.size()));
      for (std::size_t k = 0; k < keep.size(); ++k)
        Q.col(static_cast<Eigen::Index>(k)) = eig.eigenvectors().col(keep[k]);
    }
  }
  ExactQcqpResult res;
  const auto finish = [&](const Eigen::VectorXd& reduced_d) {
    res.delta = Q * reduced_d;
    res.m1 = m1.value(res.delta);
    res.m2 = m2.value(res.delta);
    return res;
  };
  if (Q.cols() == 0) {  // both models constant
    res.status = "both models constant (H_1 = H_2 = 0)";
    res.feasible = m2.a <= epsilon;
    res.mu = res.feasible ? 0.0 : std::numeric_limits<double>::infinity();
    res.min_m2 = m2.a;
    return finish(Eigen::VectorXd::Zero(0));
  }
  ReducedModel r1{Q.transpose() * H1 * Q, Q.transpose() * m1.b, m1.a};
  ReducedModel r2{Q.transpose() * H2 * Q, Q.transpose() * m2.b, m2.a};

  // mu -> 0+: argmin m_1 (then m_2). Feasible there -> the constraint is inactive.
  const Eigen::VectorXd d0 = lexicographic_minimizer(r1, r2, options.rank_tolerance);
  const double phi0 = r2.value(d0);
  res.iterations = 1;
  if (phi0 <= epsilon) {
    res.mu = 0.0;
    res.status = "constraint inactive";
    return finish(d0);
  }
  // mu -> inf: argmin m_2 (then m_1); its m_2 is the model's minimum.
  const Eigen::VectorXd dinf = lexicographic_minimizer(r2, r1, options.rank_tolerance);
  const double phiinf = r2.value(dinf);
  res.min_m2 = phiinf;
  res.iterations = 2;
  const double scale = std::max({epsilon, std::abs(phiinf), std::numeric_limits<double>::min()});
  const double tol = options.relative_tolerance * scale;
  if (epsilon < phiinf - tol) {
    res.mu = std::numeric_limits<double>::infinity();
    res.feasible = false;
    std::ostringstream msg;
    msg << "infeasible: epsilon " << epsilon << " below the model's minimum of m_2 " << phiinf
        << "; returning the m_2-minimizer";
    res.status = msg.str();
    return finish(dinf);
  }
  if (epsilon <= phiinf + tol) {
    // epsilon is the minimum of m_2: only the m_2-minimizers are feasible; no finite mu.
    res.mu = std::numeric_limits<double>::infinity();
    res.active = true;
    res.status = "epsilon equals the minimum of m_2; returning the m_2-minimizer";
    return finish(dinf);
  }

  // Active constraint: phi(mu) = m_2(d(mu)) = epsilon with mu in (0, inf). Keep a bracket
  // lo < mu* <= hi with phi(lo) > epsilon >= phi(hi); Newton on the secular form
  // psi(mu) = 1/sqrt(phi - phi_inf) - 1/sqrt(eps - phi_inf), which is close to linear in mu
  // (exactly so for a trust-region constraint), bisection whenever Newton leaves the bracket.
  Eigen::LDLT<Eigen::MatrixXd> K;
  Eigen::VectorXd d;
  double phi = 0.0, dphi = 0.0;
  const auto evaluate = [&](double mu) {
    K.compute(r1.H + mu * r2.H);
    d = K.solve(-(r1.b + mu * r2.b));
    phi = r2.value(d);
    const Eigen::VectorXd g = r2.H * d + r2.b;  // half the gradient of m_2 at d
    dphi = -2.0 * g.dot(K.solve(g));            // d phi / d mu
    ++res.iterations;
  };
  const double target = 1.0 / std::sqrt(epsilon - phiinf);
  const auto newton = [&](double mu) {
    const double gap = phi - phiinf;
    if (!(gap > 0.0) || !(dphi < 0.0)) return std::numeric_limits<double>::quiet_NaN();
    const double psi = 1.0 / std::sqrt(gap) - target;
    const double dpsi = -0.5 * dphi / (gap * std::sqrt(gap));
    return mu - psi / dpsi;
  };
  double lo = 0.0, hi = std::numeric_limits<double>::infinity();
  double mu = (t2 > 0.0 && t1 > 0.0) ? t1 / t2 : 1.0;  // the models' natural relative scale
  const double mu_max = mu * 1e30;
  double best_mu = 0.0;
  Eigen::VectorXd best_d;
  double best_phi = 0.0;
  bool converged = false;
  while (res.iterations < options.max_iterations) {
    evaluate(mu);
    if (!d.allFinite() || !std::isfinite(phi)) break;
    if (phi > epsilon) {
      lo = mu;
    } else {
      hi = mu;
      best_mu = mu;
      best_d = d;
      best_phi = phi;
    }
    if (std::abs(phi - epsilon) <= tol) {
      best_mu = mu;
      best_d = d;
      best_phi = phi;
      converged = true;
      break;
    }
    if (std::isfinite(hi) && hi - lo <= 4.0 * std::numeric_limits<double>::epsilon() * hi) {
      converged = true;  // bracket collapsed: hi is feasible and as close as doubles allow
      break;
    }
    double next = newton(mu);
    if (!std::isfinite(hi)) {
      // Still looking for a feasible mu: at least a factor 10 up, Newton if it goes further.
      next = (std::isfinite(next) && next > 10.0 * mu) ? next : 10.0 * mu;
      if (next > mu_max) break;
    } else if (!std::isfinite(next) || next <= lo || next >= hi) {
      next = (lo > 0.0 && hi / lo > 4.0) ? std::sqrt(lo * hi) : 0.5 * (lo + hi);
    }
    mu = next;
  }
  if (best_d.size() == 0) {
    // No feasible mu found below mu_max: epsilon is within rounding of min m_2.
    res.mu = std::numeric_limits<double>::infinity();
    res.active = true;
    res.status = "no finite mu reaches epsilon; returning the m_2-minimizer";
    return finish(dinf);
  }
  res.mu = best_mu;
  res.active = true;
  std::ostringstream msg;
  msg << (converged ? "active, mu found" : "active, iteration limit; best feasible mu")
      << " (|m_2 - eps| = " << std::abs(best_phi - epsilon) << ")";
  res.status = msg.str();
  return finish(best_d);
}

StepResult ExactQcqpBackend::solve(const Subproblem& sp) {
  if (sp.kind != ScalarizationKind::kEpsilonConstraint || sp.lin == nullptr) {
    throw Error("exact: needs an epsilon-constraint subproblem with a linearization");
  }
  const ExactQcqpResult q = solve_qcqp_exact(sp.lin->f1, sp.lin->f2, sp.epsilon, options_);
  StepResult r;
  r.delta = q.delta;
  r.multiplier = q.mu;
  r.feasible = q.feasible;
  r.iterations = q.iterations;
  r.status = q.status;
  return r;
}

}  // namespace bivo::solvers
