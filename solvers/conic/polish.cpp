#include "solvers/conic/polish.h"

#include <algorithm>
#include <cmath>

#include <Eigen/LU>
#include <Eigen/QR>

namespace bivo::solvers::conic {

namespace {

// Fixed costs in operations (the work counts' unit, about a nanosecond each on small
// systems): a call (its vectors, the classification) and a Newton step (the LU's set-up).
constexpr double kCallWork = 2000.0, kStepWork = 800.0;

// Partial-pivoting LU of a K x K matrix: 2/3 K^3 operations, blocked and vectorized. Charged
// K^3 / 3 (plus 2 K^2 and kStepWork at the call): above its measured time at every K from 4 to
// 128 in the unit the KKT system's counts run at (0.5-1 ns).
double lu_work(int K) { return static_cast<double>(K) * K * K / 3.0; }

// M = [H B^T; B 0] with B of r x n: with more rows than columns (a degenerate vertex, or a
// wrong guess) M is singular whatever the values. (With fewer rows and no boundary cones it
// is singular too, but Newton from the iterate may still reach a point of a non-vertex
// optimal face: such a guess is tried.)
bool singular_shape(int n, int r) { return r > n; }

}  // namespace

Polisher::Polisher(const ConicProblem& problem, const ConstraintMatrix& G, const ConeProduct& cones,
                   PolishSettings settings)
    : sp_(problem), G_(G), cones_(cones), settings_(settings) {}

bool Polisher::set_up() {
  if (ready_) return true;
  const int nsoc = cones_.soc_count();
  const double n = sp_.num_variables();
  g_work_ = 2.0 * (G_.dense() ? static_cast<double>(G_.rows()) * G_.cols() : G_.sparse().nonZeros());
  // Each cone reads its own rows of G: one pass over G for all of them.
  if (!charge(g_work_ + nsoc * 4.0 * n * n + 2.0 * static_cast<double>(sp_.A.nonZeros()))) return false;
  gram_.resize(nsoc);
  head_.resize(nsoc);
  u_.resize(nsoc);
  eta_.resize(nsoc);
  Eigen::VectorXd jh;
  for (int k = 0; k < nsoc; ++k) {
    const int o = cones_.soc_offset(k), d = cones_.spec().soc[k];
    head_[k] = G_.dense_rows(o, 1).transpose();
    gram_[k] = G_.dense_gram(o, d);
    gram_[k].noalias() -= 2.0 * head_[k] * head_[k].transpose();
    jh = -sp_.h.segment(o, d);
    jh[0] = -jh[0];
    u_[k] = Eigen::VectorXd::Zero(sp_.num_variables());
    G_.add_rows_multiply_transpose(o, d, 1.0, jh, u_[k]);
    const double h1 = d > 1 ? sp_.h.segment(o + 1, d - 1).norm() : 0.0;
    eta_[k] = (sp_.h[o] - h1) * (sp_.h[o] + h1);
  }
  At_ = Eigen::MatrixXd(sp_.A.transpose());
  norm_c_ = 1.0 + sp_.c.lpNorm<Eigen::Infinity>();
  norm_b_ = 1.0 + sp_.b.lpNorm<Eigen::Infinity>();
  norm_h_ = 1.0 + sp_.h.lpNorm<Eigen::Infinity>();
  ready_ = true;
  return true;
}

// The larger member of each complementary eigen-pair survives (see polish.h).
void Polisher::classify(const Eigen::VectorXd& s, const Eigen::VectorXd& z, double s_scale, double z_scale) {
  const int l = cones_.spec().nonnegative;
  orthant_kind_.assign(l, Kind::kInactive);
  for (int i = 0; i < l; ++i) {
    if (s[i] / s_scale < z[i] / z_scale) orthant_kind_[i] = Kind::kApex;
  }
  soc_kind_.assign(cones_.soc_count(), Kind::kInactive);
  for (int k = 0; k < cones_.soc_count(); ++k) {
    const int o = cones_.soc_offset(k), d = cones_.spec().soc[k];
    const double ns1 = d > 1 ? s.segment(o + 1, d - 1).norm() / s_scale : 0.0;
    const double nz1 = d > 1 ? z.segment(o + 1, d - 1).norm() / z_scale : 0.0;
    const double s0 = s[o] / s_scale, z0 = z[o] / z_scale;
    Kind kind = Kind::kInactive;
    if (s0 + ns1 < z0 - nz1) {
      kind = Kind::kApex;  // both eigenvalues of s lose: s = 0
    } else if (s0 - ns1 < z0 + nz1) {
      kind = d > 1 ? Kind::kBoundary : Kind::kApex;  // a cone of dimension 1 is an orthant entry
    }
    soc_kind_[k] = kind;
  }
  // An apex guess for a cone too large for the dense system (s = 0 on all its rows) is
  // unusable; its next most likely state is the boundary (the small eigenvalue of s zero).
  int size = sp_.num_variables() + sp_.num_equalities();
  for (int i = 0; i < l; ++i) size += orthant_kind_[i] == Kind::kApex ? 1 : 0;
  for (int k = 0; k < cones_.soc_count(); ++k) {
    size += soc_kind_[k] == Kind::kApex ? cones_.spec().soc[k] : soc_kind_[k] == Kind::kBoundary ? 1 : 0;
  }
  for (int k = 0; k < cones_.soc_count() && size > settings_.max_system_size; ++k) {
    if (soc_kind_[k] == Kind::kApex && cones_.spec().soc[k] > 1) {
      soc_kind_[k] = Kind::kBoundary;
      size -= cones_.spec().soc[k] - 1;
    }
  }
  collect();
}

void Polisher::collect() {
  apex_rows_.clear();
  boundary_.clear();
  for (int i = 0; i < cones_.spec().nonnegative; ++i) {
    if (orthant_kind_[i] == Kind::kApex) apex_rows_.push_back(i);
  }
  for (int k = 0; k < cones_.soc_count(); ++k) {
    if (soc_kind_[k] == Kind::kBoundary) boundary_.push_back(k);
    if (soc_kind_[k] == Kind::kApex) {
      for (int i = 0; i < cones_.spec().soc[k]; ++i) apex_rows_.push_back(cones_.soc_offset(k) + i);
    }
  }
}

bool Polisher::polish(const Variables& v, Variables& out, double budget) {
  newton_steps_ = 0;
  work_ = 0.0;
  budget_ = budget;
  over_ = false;
  tried_.clear();
  if (!(v.tau > 0.0) || !charge(kCallWork + 8.0 * sp_.num_cone_rows())) return false;
  s0_ = v.s / v.tau;
  z0_ = v.z / v.tau;
  classify(s0_, z0_);
  if (solve_guess(v, s0_, z0_, out)) return true;
  const std::vector<Kind> orthant = orthant_kind_, soc = soc_kind_;
  // s and z come in different units (equilibration balances G, not s against z): a second
  // guess compares them relative to their own largest entries, if that guess differs.
  const double s_scale = s0_.lpNorm<Eigen::Infinity>(), z_scale = z0_.lpNorm<Eigen::Infinity>();
  if (last_out_of_budget()) return false;
  if (s_scale > 0.0 && z_scale > 0.0) {
    classify(s0_, z0_, s_scale, z_scale);
    if ((orthant != orthant_kind_ || soc != soc_kind_) && solve_guess(v, s0_, z0_, out)) return true;
  }
  // With few second-order cones, the guesses one cone away from the first (boundary <->
  // inactive, apex -> boundary): early iterates often tell all but one cone right, and a
  // wrong guess is refused on the quadratic forms, before any pass over G.
  if (cones_.soc_count() > settings_.max_neighbour_cones) return false;
  for (int k = 0; k < cones_.soc_count(); ++k) {
    if (cones_.spec().soc[k] < 2 || last_out_of_budget()) continue;
    orthant_kind_ = orthant;
    soc_kind_ = soc;
    soc_kind_[k] = soc[k] == Kind::kBoundary ? Kind::kInactive : Kind::kBoundary;
    collect();
    if (solve_guess(v, s0_, z0_, out)) return true;
  }
  return false;
}

double Polisher::evaluation_work(bool quadratic) const {
  const double n = sp_.num_variables(), p = sp_.num_equalities();
  const double nb = static_cast<double>(boundary_.size()), na = static_cast<double>(apex_rows_.size());
  const double w = kStepWork / 4 + nb * (2.0 * n * n + 6.0 * n) + 2.0 * n * (p + na) + 4.0 * (n + p + nb + na);
  return quadratic ? w : w + 2.0 * g_work_ + 2.0 * sp_.num_cone_rows();
}

double Polisher::evaluate(const Eigen::VectorXd& uu, bool quadratic, Eigen::VectorXd& s, Eigen::MatrixXd& a,
                          Eigen::VectorXd& F) {
  const int n = sp_.num_variables(), p = sp_.num_equalities();
  const int nb = static_cast<int>(boundary_.size()), na = static_cast<int>(apex_rows_.size());
  const auto x = uu.head(n);
  const double nc = norm_c_, nbv = norm_b_, nh = norm_h_;
  F.resize(n + p + nb + na);
  a.resize(n, nb);
  psi_scale_.resize(nb);
  F.head(n) = sp_.c;
  if (p > 0) F.head(n).noalias() += At_ * uu.segment(n, p);
  if (na > 0) F.head(n).noalias() += Ga_.transpose() * uu.tail(na);
  if (!quadratic) {
    s.resize(sp_.num_cone_rows());
    G_.multiply(x, s);
    s = sp_.h - s;
  }
  double merit_psi = 0.0;
  for (int b = 0; b < nb; ++b) {
    const int k = boundary_[b], o = cones_.soc_offset(k), d = cones_.spec().soc[k];
    double s0, n1, psi;
    if (quadratic) {
      // a_k = u_k + P_k x, psi = eta/2 - u^T x - x^T P x / 2, s0 = h0 - g^T x.
      a.col(b).noalias() = gram_[k] * x;
      psi = 0.5 * eta_[k] - u_[k].dot(x) - 0.5 * x.dot(a.col(b));
      a.col(b) += u_[k];
      s0 = sp_.h[o] - head_[k].dot(x);
      n1 = std::sqrt(std::max(0.0, s0 * s0 - 2.0 * psi));
    } else {
      js_ = -s.segment(o, d);
      js_[0] = -js_[0];
      a.col(b).setZero();
      G_.add_rows_multiply_transpose(o, d, 1.0, js_, a.col(b));
      s0 = s[o];
      n1 = js_.tail(d - 1).norm();
      psi = 0.5 * (s0 - n1) * (s0 + n1);
    }
    F.head(n).noalias() += uu[n + p + b] * a.col(b);
    F[n + p + b] = -psi;
    psi_scale_[b] = 0.5 * (std::abs(s0) + n1) * (std::abs(s0) + n1) + 1e-300;
    merit_psi = std::max(merit_psi, std::abs(psi) / psi_scale_[b]);
  }
  if (p > 0) F.segment(n, p).noalias() = sp_.A * x - sp_.b;
  double merit_apex = 0.0;
  for (int r = 0; r < na; ++r) {
    const double sr = quadratic ? sp_.h[apex_rows_[r]] - Ga_.row(r).dot(x) : s[apex_rows_[r]];
    F[n + p + nb + r] = -sr;
    merit_apex = std::max(merit_apex, std::abs(sr));
  }
  return std::max({F.head(n).lpNorm<Eigen::Infinity>() / nc,
                   p > 0 ? F.segment(n, p).lpNorm<Eigen::Infinity>() / nbv : 0.0, merit_psi, merit_apex / nh});
}

// Newton with backtracking on the merit until it stops falling (quadratic convergence,
// then rounding) or a step no longer moves u. Far from the solution (the first tries start
// at a relative gap of 0.1 or more) a full step can overshoot: halve it up to 4 times. Near
// the rounding level a step must halve the merit or Newton is done. Only improving steps
// are taken, so u is always the best point so far, and s_, a_, F_ belong to it.
bool Polisher::newton(Eigen::VectorXd& u, bool quadratic, int max_steps, double& merit, int& steps) {
  const int n = sp_.num_variables(), p = sp_.num_equalities();
  const int nb = static_cast<int>(boundary_.size()), na = static_cast<int>(apex_rows_.size());
  const int N = n + p + nb + na, r = N - n;
  if (singular_shape(n, r)) return false;
  if (!charge(evaluation_work(quadratic))) return false;
  merit = evaluate(u, quadratic, s_, a_, F_);
  // Far from the solution, steps must decrease the weighted 2-norm of F (weights fixed at the
  // start: the merit's normalizations), a smooth function Newton's direction descends on.
  Eigen::VectorXd weight = Eigen::VectorXd::Constant(N, 1.0 / norm_c_);
  weight.segment(n, p).setConstant(1.0 / norm_b_);
  for (int b = 0; b < nb; ++b) weight[n + p + b] = 1.0 / psi_scale_[b];
  weight.tail(na).setConstant(1.0 / norm_h_);
  double norm2 = F_.cwiseProduct(weight).squaredNorm();
  Eigen::VectorXd trial(N), du(N);
  // M = [H B^T; B 0] with B = [A; a^T; G_apex] of r rows. With B square (a vertex: as many
  // active constraints as variables) B dx = F2 fixes dx and B^T dw = F1 - H dx the rest, so
  // only B is factored, an eighth of M's operations.
  const bool square = r == n;
  for (steps = 0; std::isfinite(merit) && merit > 1e-15 && steps < max_steps;) {
    // Without boundary cones the matrix is the guess's constant one (A, the apex rows of G):
    // factored once per guess (an LP's polish: one factorization for both stages).
    if (nb > 0 || !lu_current_) {
      const int K = square ? n : N;
      if (square) {
        B_.resize(n, n);
        if (p > 0) B_.topRows(p) = At_.transpose();
        B_.middleRows(p, nb) = a_.transpose();
        if (na > 0) B_.bottomRows(na) = Ga_;
      } else {
        M_.setZero(N, N);
        for (int b = 0; b < nb; ++b) M_.topLeftCorner(n, n) += u[n + p + b] * gram_[boundary_[b]];
        if (p > 0) {
          M_.block(0, n, n, p) = At_;
          M_.block(n, 0, p, n) = At_.transpose();
        }
        M_.block(0, n + p, n, nb) = a_;
        M_.block(n + p, 0, nb, n) = a_.transpose();
        if (na > 0) {
          M_.block(0, n + p + nb, n, na) = Ga_.transpose();
          M_.block(n + p + nb, 0, na, n) = Ga_;
        }
      }
      if (!charge(kStepWork + lu_work(K) + 2.0 * nb * n * n + 2.0 * K * K)) return false;
      lu_.compute(square ? B_ : M_);
      lu_current_ = nb == 0;
      // Partial pivoting reveals no rank; a pivot at rounding level next to the largest
      // says singular as full pivoting's threshold would (a near-singular guess is refused
      // downstream anyway: its step does not lower the merit).
      const auto pivots = lu_.matrixLU().diagonal().cwiseAbs();
      lu_invertible_ =
          pivots.allFinite() && pivots.minCoeff() > Eigen::NumTraits<double>::epsilon() * K * pivots.maxCoeff();
    } else if (!charge(kStepWork / 4 + 2.0 * N * N)) {
      return false;
    }
    if (!lu_invertible_) return false;
    if (square) {
      if (!charge(4.0 * n * n + 2.0 * nb * n * n)) return false;
      du.head(n) = lu_.solve(F_.tail(r));
      Eigen::VectorXd g = F_.head(n);
      for (int b = 0; b < nb; ++b) g.noalias() -= u[n + p + b] * (gram_[boundary_[b]] * du.head(n));
      du.tail(r) = lu_.transpose().solve(g);
    } else {
      du = lu_.solve(F_);
    }
    const bool near = merit < 1e-8;
    bool accepted = false;
    double t = 1.0, taken = 0.0;
    for (int halving = 0; halving < (near ? 1 : quadratic ? 20 : 5) && !accepted; ++halving, t *= 0.5) {
      trial = u - t * du;
      if (!charge(evaluation_work(quadratic))) return false;
      const double m_trial = evaluate(trial, quadratic, s_trial_, a_trial_, F_trial_);
      const double n2_trial = F_trial_.cwiseProduct(weight).squaredNorm();
      accepted = std::isfinite(m_trial) &&
                 (near ? m_trial < 0.5 * merit : n2_trial <= (1.0 - 1e-4 * t) * norm2 || m_trial < merit);
      if (accepted) {
        u.swap(trial);
        s_.swap(s_trial_);
        a_.swap(a_trial_);
        F_.swap(F_trial_);
        merit = m_trial;
        norm2 = n2_trial;
        taken = t;
      }
    }
    if (!accepted) break;
    ++steps;
    if (taken == 1.0 && du.lpNorm<Eigen::Infinity>() <= 1e-14 * (1.0 + u.lpNorm<Eigen::Infinity>())) break;
  }
  return std::isfinite(merit);
}

bool Polisher::consistent(const Eigen::VectorXd& u) {
  const int n = sp_.num_variables(), p = sp_.num_equalities();
  const auto x = u.head(n);
  bool ok = true;
  for (std::size_t b = 0; b < boundary_.size(); ++b) {
    const int k = boundary_[b];
    if (!(u[n + p + static_cast<int>(b)] >= 0.0) || !(sp_.h[cones_.soc_offset(k)] - head_[k].dot(x) > 0.0)) {
      soc_kind_[k] = Kind::kInactive;
      ok = false;
    }
  }
  for (int k = 0; k < cones_.soc_count(); ++k) {
    if (soc_kind_[k] != Kind::kInactive || cones_.spec().soc[k] < 2 ||
        std::find(boundary_.begin(), boundary_.end(), k) != boundary_.end()) {
      continue;
    }
    // s_k in K: head > 0 and psi >= 0, up to the quadratic forms' rounding.
    const double s0 = sp_.h[cones_.soc_offset(k)] - head_[k].dot(x);
    const double psi = 0.5 * eta_[k] - u_[k].dot(x) - 0.5 * x.dot(gram_[k] * x);
    if (!(s0 > 0.0) || psi < -1e-6 * s0 * s0) {
      soc_kind_[k] = Kind::kBoundary;
      ok = false;
    }
  }
  return ok;
}

bool Polisher::relayout(Eigen::VectorXd& u) {
  const int n = sp_.num_variables(), p = sp_.num_equalities(), na = static_cast<int>(apex_rows_.size());
  collect();
  const int nb = static_cast<int>(boundary_.size());
  Eigen::VectorXd w(n + p + nb + na);
  w.head(n + p) = u.head(n + p);
  w.tail(na) = u.tail(na);  // the apex cones are never switched
  w.segment(n + p, nb).setOnes();
  // Multipliers of the new guess: least squares on the dual residual at x (F1 is affine in
  // them), kept positive so the Newton matrix stays regular.
  if (!charge(evaluation_work(true) + 4.0 * n * nb * nb)) return false;
  evaluate(w, true, s_, a_, F_);
  if (nb > 0) {
    const Eigen::VectorXd r0 = F_.head(n) - a_ * w.segment(n + p, nb);
    Eigen::VectorXd lambda = a_.colPivHouseholderQr().solve(-r0);
    const double floor = 1e-6 * std::max(1.0, lambda.cwiseAbs().maxCoeff());
    for (int b = 0; b < nb; ++b) lambda[b] = std::isfinite(lambda[b]) ? std::max(lambda[b], floor) : 1.0;
    w.segment(n + p, nb) = lambda;
  }
  u.swap(w);
  return true;
}

bool Polisher::solve_guess(const Variables& v, const Eigen::VectorXd& s0, const Eigen::VectorXd& z0, Variables& out) {
  newton_steps_ = true_steps_ = 0;
  lu_current_ = false;
  const int n = sp_.num_variables(), p = sp_.num_equalities(), m = sp_.num_cone_rows();
  int nb = static_cast<int>(boundary_.size());
  const int na = static_cast<int>(apex_rows_.size());
  if (n + p + nb + na > settings_.max_system_size || singular_shape(n, p + nb + na)) return false;
  if (!set_up()) return false;

  // Unknowns u = (x, y, lambda, z_apex), started from the iterate.
  Eigen::VectorXd u(n + p + nb + na);
  u.head(n) = v.x / v.tau;
  u.segment(n, p) = v.y / v.tau;
  for (int b = 0; b < nb; ++b) {
    const int o = cones_.soc_offset(boundary_[b]);
    u[n + p + b] = z0[o] / s0[o];  // z = lambda J s: z0 = lambda s0
  }
  for (int a = 0; a < na; ++a) u[n + p + nb + a] = z0[apex_rows_[a]];
  if (!charge(2.0 * na * n + 4.0 * (n + p + nb + na))) return false;
  Ga_.resize(na, n);
  for (int a = 0; a < na; ++a) Ga_.row(a) = G_.dense_rows(apex_rows_[a], 1);

  // Stage 1 on the quadratic forms: Newton on the guess; where its solution contradicts the
  // guess (a boundary cone's multiplier < 0, an inactive cone's slack outside K) those cones
  // switch and Newton goes on from there, a primal active-set step at no cost in passes.
  double merit = 0.0;
  int steps = 0;
  for (int attempt = 0;; ++attempt) {
    // Each guess once per polish call (the first guesses and the switched ones overlap).
    std::vector<Kind> key = soc_kind_;
    key.insert(key.end(), orthant_kind_.begin(), orthant_kind_.end());
    if (std::find(tried_.begin(), tried_.end(), key) != tried_.end()) return false;
    tried_.push_back(std::move(key));
    if (!newton(u, true, settings_.max_quadratic_steps, merit, steps)) return false;
    newton_steps_ += steps;
    if (!(merit < 1e-8)) return false;  // not converged: no verdict on this guess
    if (consistent(u)) break;
    if (attempt >= settings_.max_switches) return false;
    if (!relayout(u)) return false;
    nb = static_cast<int>(boundary_.size());
    if (n + p + nb + na > settings_.max_system_size) return false;
  }
  // Stage 2 on the true residuals.
  if (!newton(u, false, settings_.max_newton_steps, merit, steps)) return false;
  true_steps_ = steps;
  newton_steps_ += steps;

  // Assemble (x, y, s, z); the guess was wrong if a multiplier or slack leaves its cone.
  out.x = u.head(n);
  out.y = u.segment(n, p);
  out.s.swap(s_);
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
