#include "solvers/conic/polish.h"

#include <algorithm>
#include <cmath>

#include <Eigen/LU>

namespace bivo::solvers::conic {

Polisher::Polisher(const ConicProblem& problem, const ConstraintMatrix& G, const ConeProduct& cones,
                   PolishSettings settings)
    : sp_(problem), G_(G), cones_(cones), settings_(settings) {}

void Polisher::set_up() {
  if (ready_) return;
  gram_.resize(cones_.soc_count());
  for (int k = 0; k < cones_.soc_count(); ++k) {
    const int o = cones_.soc_offset(k);
    const Eigen::VectorXd head = G_.dense_rows(o, 1).transpose();
    gram_[k] = Eigen::MatrixXd(G_.gram(o, cones_.spec().soc[k]));
    gram_[k].noalias() -= 2.0 * head * head.transpose();
  }
  ready_ = true;
}

// The larger member of each complementary eigen-pair survives (see polish.h).
void Polisher::classify(const Eigen::VectorXd& s, const Eigen::VectorXd& z) {
  const int l = cones_.spec().nonnegative;
  orthant_kind_.assign(l, Kind::kInactive);
  apex_rows_.clear();
  boundary_.clear();
  for (int i = 0; i < l; ++i) {
    if (s[i] < z[i]) {
      orthant_kind_[i] = Kind::kApex;
      apex_rows_.push_back(i);
    }
  }
  soc_kind_.assign(cones_.soc_count(), Kind::kInactive);
  for (int k = 0; k < cones_.soc_count(); ++k) {
    const int o = cones_.soc_offset(k), d = cones_.spec().soc[k];
    const double ns1 = d > 1 ? s.segment(o + 1, d - 1).norm() : 0.0;
    const double nz1 = d > 1 ? z.segment(o + 1, d - 1).norm() : 0.0;
    Kind kind = Kind::kInactive;
    if (s[o] + ns1 < z[o] - nz1) {
      kind = Kind::kApex;  // both eigenvalues of s lose: s = 0
    } else if (s[o] - ns1 < z[o] + nz1) {
      kind = d > 1 ? Kind::kBoundary : Kind::kApex;  // a cone of dimension 1 is an orthant entry
    }
    soc_kind_[k] = kind;
    if (kind == Kind::kBoundary) boundary_.push_back(k);
    if (kind == Kind::kApex) {
      for (int i = 0; i < d; ++i) apex_rows_.push_back(o + i);
    }
  }
}

bool Polisher::polish(const Variables& v, Variables& out) {
  newton_steps_ = 0;
  if (!(v.tau > 0.0)) return false;
  const Eigen::VectorXd s0 = v.s / v.tau, z0 = v.z / v.tau;
  classify(s0, z0);
  if (solve_guess(v, s0, z0, out)) return true;
  // s and z come in different units (equilibration balances G, not s against z): a second
  // guess compares them relative to their own largest entries, if that guess differs.
  const double s_scale = s0.lpNorm<Eigen::Infinity>(), z_scale = z0.lpNorm<Eigen::Infinity>();
  if (!(s_scale > 0.0) || !(z_scale > 0.0)) return false;
  const std::vector<Kind> orthant = orthant_kind_, soc = soc_kind_;
  classify(s0 / s_scale, z0 / z_scale);
  if (orthant == orthant_kind_ && soc == soc_kind_) return false;
  return solve_guess(v, s0, z0, out);
}

bool Polisher::solve_guess(const Variables& v, const Eigen::VectorXd& s0, const Eigen::VectorXd& z0, Variables& out) {
  newton_steps_ = 0;
  const int n = sp_.num_variables(), p = sp_.num_equalities(), m = sp_.num_cone_rows();
  const int nb = static_cast<int>(boundary_.size()), na = static_cast<int>(apex_rows_.size());
  const int N = n + p + nb + na;
  if (N > settings_.max_system_size) return false;
  set_up();

  // Unknowns u = (x, y, lambda, z_apex), started from the iterate.
  Eigen::VectorXd u(N);
  u.head(n) = v.x / v.tau;
  u.segment(n, p) = v.y / v.tau;
  for (int b = 0; b < nb; ++b) {
    const int o = cones_.soc_offset(boundary_[b]);
    u[n + p + b] = z0[o] / s0[o];  // z = lambda J s: z0 = lambda s0
  }
  for (int a = 0; a < na; ++a) u[n + p + nb + a] = z0[apex_rows_[a]];

  Eigen::MatrixXd Ga(na, n);
  for (int a = 0; a < na; ++a) Ga.row(a) = G_.dense_rows(apex_rows_[a], 1);
  const Eigen::MatrixXd At = Eigen::MatrixXd(sp_.A.transpose());
  const double nc = 1.0 + sp_.c.lpNorm<Eigen::Infinity>(), nbv = 1.0 + sp_.b.lpNorm<Eigen::Infinity>(),
               nh = 1.0 + sp_.h.lpNorm<Eigen::Infinity>();

  Eigen::VectorXd s(m), F(N), js;
  Eigen::MatrixXd a(n, nb), M(N, N);
  // Residuals at u: s = h - G x, the a_k, F = (F1, F2, -psi, -s_apex) (Newton: M du = -F).
  auto evaluate = [&](const Eigen::VectorXd& uu) {
    const auto x = uu.head(n);
    G_.multiply(x, s);
    s = sp_.h - s;
    F.head(n) = sp_.c;
    if (p > 0) F.head(n).noalias() += At * uu.segment(n, p);
    if (na > 0) F.head(n).noalias() += Ga.transpose() * uu.tail(na);
    double merit_psi = 0.0;
    for (int b = 0; b < nb; ++b) {
      const int k = boundary_[b], o = cones_.soc_offset(k), d = cones_.spec().soc[k];
      js = s.segment(o, d);
      js.tail(d - 1) = -js.tail(d - 1);
      a.col(b).setZero();
      G_.add_rows_multiply_transpose(o, d, 1.0, js, a.col(b));
      F.head(n).noalias() += uu[n + p + b] * a.col(b);
      const double ns1 = js.tail(d - 1).norm();
      const double psi = 0.5 * (s[o] - ns1) * (s[o] + ns1);
      F[n + p + b] = -psi;
      merit_psi = std::max(merit_psi, std::abs(s[o] - ns1) / (std::abs(s[o]) + ns1 + 1e-300));
    }
    if (p > 0) F.segment(n, p).noalias() = sp_.A * x - sp_.b;
    double merit_apex = 0.0;
    for (int r = 0; r < na; ++r) {
      F[n + p + nb + r] = -s[apex_rows_[r]];
      merit_apex = std::max(merit_apex, std::abs(s[apex_rows_[r]]));
    }
    return std::max({F.head(n).lpNorm<Eigen::Infinity>() / nc,
                     p > 0 ? F.segment(n, p).lpNorm<Eigen::Infinity>() / nbv : 0.0, merit_psi, merit_apex / nh});
  };

  // Newton with backtracking on the merit until it stops falling (quadratic convergence,
  // then rounding) or a step no longer moves u. Far from the solution (the first tries start
  // at a relative gap of 0.1) a full step can overshoot: halve it up to 4 times. Near the
  // rounding level a step must halve the merit or Newton is done. Only improving steps are
  // taken, so u is always the best point so far.
  double merit = evaluate(u);
  bool evaluated_u = true;  // s, a and F currently belong to u (not to a rejected trial)
  Eigen::VectorXd trial(N);
  for (int step = 0; std::isfinite(merit) && merit > 1e-15 && step < settings_.max_newton_steps; ++step) {
    M.setZero();
    for (int b = 0; b < nb; ++b) M.topLeftCorner(n, n) += u[n + p + b] * gram_[boundary_[b]];
    if (p > 0) {
      M.block(0, n, n, p) = At;
      M.block(n, 0, p, n) = At.transpose();
    }
    M.block(0, n + p, n, nb) = a;
    M.block(n + p, 0, nb, n) = a.transpose();
    if (na > 0) {
      M.block(0, n + p + nb, n, na) = Ga.transpose();
      M.block(n + p + nb, 0, na, n) = Ga;
    }
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(M);
    if (!lu.isInvertible()) return false;
    const Eigen::VectorXd du = lu.solve(F);
    const bool near = merit < 1e-8;
    bool accepted = false;
    double t = 1.0, taken = 0.0;
    for (int halving = 0; halving < (near ? 1 : 5) && !accepted; ++halving, t *= 0.5) {
      trial = u - t * du;
      const double m_trial = evaluate(trial);
      accepted = std::isfinite(m_trial) && m_trial < (near ? 0.5 : 1.0) * merit;
      if (accepted) {
        u.swap(trial);
        merit = m_trial;
        taken = t;
      }
    }
    evaluated_u = accepted;
    if (!accepted) break;
    newton_steps_ = step + 1;
    if (taken == 1.0 && du.lpNorm<Eigen::Infinity>() <= 1e-14 * (1.0 + u.lpNorm<Eigen::Infinity>())) break;
  }
  if (!std::isfinite(merit)) return false;
  if (!evaluated_u) evaluate(u);

  // Assemble (x, y, s, z); the guess was wrong if a multiplier or slack leaves its cone.
  out.x = u.head(n);
  out.y = u.segment(n, p);
  out.s = s;
  out.z = Eigen::VectorXd::Zero(m);
  out.tau = 1.0;
  out.kappa = 0.0;
  for (int a_i = 0; a_i < na; ++a_i) {
    out.z[apex_rows_[a_i]] = u[n + p + nb + a_i];
    out.s[apex_rows_[a_i]] = 0.0;
  }
  for (int i = 0; i < cones_.spec().nonnegative; ++i) {
    if (orthant_kind_[i] == Kind::kInactive ? !(out.s[i] >= 0.0) : !(out.z[i] >= 0.0)) return false;
  }
  for (int b = 0; b < nb; ++b) {
    const int k = boundary_[b], o = cones_.soc_offset(k), d = cones_.spec().soc[k];
    const double lambda = u[n + p + b];
    const double ns1 = out.s.segment(o + 1, d - 1).norm();
    if (!(lambda >= 0.0) || !(out.s[o] > 0.0)) return false;
    out.s[o] = std::max(out.s[o], ns1);  // on the boundary up to rounding
    out.z[o] = lambda * out.s[o];
    out.z.segment(o + 1, d - 1) = -lambda * out.s.segment(o + 1, d - 1);
  }
  for (int k = 0; k < cones_.soc_count(); ++k) {
    const int o = cones_.soc_offset(k), d = cones_.spec().soc[k];
    const Eigen::VectorXd& u_k = soc_kind_[k] == Kind::kApex ? out.z : out.s;
    if (soc_kind_[k] == Kind::kBoundary) continue;
    const double n1 = d > 1 ? u_k.segment(o + 1, d - 1).norm() : 0.0;
    if (!(u_k[o] >= n1)) return false;
  }
  return out.x.allFinite() && out.y.allFinite() && out.s.allFinite() && out.z.allFinite();
}

}  // namespace bivo::solvers::conic
