#include "solvers/conic/ipm_solver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <ostream>
#include <utility>

#include "solvers/conic/certificate.h"
#include "solvers/conic/cones.h"
#include "solvers/conic/infinite_rows.h"
#include "solvers/conic/ipm_log.h"
#include "solvers/conic/kkt_system.h"
#include "solvers/conic/polish.h"
#include "solvers/conic/residuals.h"
#include "solvers/conic/variables.h"

namespace bivo::solvers::conic {

namespace {

struct Direction {
  Eigen::VectorXd dx, dy, dz, ds_scaled, dz_scaled;  // ds_scaled = W^{-1} ds, dz_scaled = W dz
  double dtau = 0.0, dkappa = 0.0;
};

class Solver {
 public:
  // One solve: the set-up (scaled copy of the data, KKT pattern, ordering) into this
  // object's buffers, then the iterations; the result stays in result_.
  IpmResult& run(const ConicProblem& original, const IpmSettings& settings, IpmClock* clock) {
    setup(original, settings, clock);
    return iterate();
  }

 private:
  void setup(const ConicProblem& original, const IpmSettings& settings, IpmClock* clock) {
    op_ = &original;
    st_ = settings;
    strict_ = strict_tolerances(settings);
    reduced_ = reduced_tolerances(settings);
    clock_ = clock;
    PhaseScope phase(clock_, IpmPhase::kEquilibration);
    // The scaled problem: c, A, b, h copied and scaled here (into the buffers of the last
    // solve); G only once, scaled on the way into its product layout (ConstraintMatrix).
    const int n = original.num_variables();
    sp_.c = original.c;
    sp_.A = original.A;
    sp_.b = original.b;
    sp_.h = original.h;
    sp_.cones = original.cones;
    if (sp_.A.cols() != n) sp_.A.resize(0, n);
    equilibration_factors(original, st_.equilibration_passes, eq_);
    scale_vectors_and_equalities(sp_, eq_);
    sp_.A.makeCompressed();  // the KKT system reads the compressed arrays directly
    if (cones_) {
      *cones_ = ConeProduct(sp_.cones);  // same object: the KKT system and polisher refer to it
    } else {
      cones_ = std::make_unique<ConeProduct>(sp_.cones);
    }
    KktSettings ks;
    ks.static_regularization = st_.static_regularization;
    ks.max_refinement_steps = st_.max_refinement_steps;
    if (original.has_dense_G()) {
      gmat_.assign(original.dense_G, eq_.row_cone, eq_.col);
    } else if (original.G.cols() == n) {
      gmat_.assign(original.G, eq_.row_cone, eq_.col);
    } else {
      gmat_.assign(SparseMatrix(original.num_cone_rows(), n), eq_.row_cone, eq_.col);
    }
    gmat_.set_clock(clock_);
    kkt_.setup(sp_.A, gmat_, *cones_, ks, clock_);
    if (st_.polish) {
      if (!polisher_) polisher_ = std::make_unique<Polisher>(sp_, gmat_, *cones_);
      polisher_->reset();
    }
    n_ = n;
    p_ = sp_.num_equalities();
    m_ = sp_.num_cone_rows();
    cbh_.resize(n_ + p_ + m_);
    cbh_ << -sp_.c, sp_.b, sp_.h;
    e_.setZero(m_);
    cones_->add_identity(e_, 1.0);
    best_score_ = std::numeric_limits<double>::infinity();
    stalled_ = 0;
    is_polished_ = false;
    polish_deferred_ = false;
    polish_work_ = 0.0;
    polish_wait_ = 0.0;
    // The work of the set-up outside the KKT system: validation, equilibration (a few
    // sweeps over the data) and the scaled copies.
    const double data = static_cast<double>(original.A.nonZeros()) + (original.has_dense_G()
                                                                          ? static_cast<double>(original.dense_G.size())
                                                                          : static_cast<double>(original.G.nonZeros()));
    g_work_ = 2.0 * (gmat_.dense() ? static_cast<double>(m_) * n_ : static_cast<double>(gmat_.sparse().nonZeros()));
    residual_work_ = 2.0 * g_work_ + 4.0 * static_cast<double>(sp_.A.nonZeros()) + 12.0 * (n_ + p_ + m_);
    work_ = 5000.0 + 8.0 * data + 8.0 * (n_ + p_ + m_);
  }
  // Operations of the interior-point method so far (set-up, iterations), counted from the
  // patterns: the polish may spend at most as much (polish_exit).
  double ipm_work() const { return work_ + kkt_.work(); }

  IpmResult& iterate();
  bool initialize();
  // refine = false for the predictor: it only sets sigma and the second-order term.
  bool direction(double sigma, const Eigen::VectorXd& bs, double rk, Direction& d, bool refine = true);
  double max_step(const Direction& d) const;
  IpmResult& finish(IpmStatus status, const Variables& v, int iterations);
  // Polishes v and returns the finished result when the polished point is certified optimal
  // at tolerances t (allow_reduced: or at the reduced ones), else nullptr with the state
  // left as it was: the caller goes on with the interior point.
  IpmResult* polish_exit(const Variables& v, const Tolerances& t, int iterations, bool allow_reduced);
  // Numerical trouble or the iteration limit: like ECOS, accept the best iterate at the
  // reduced-accuracy tolerances if it meets them (flagged), else report the failure.
  IpmResult& stop_early(IpmStatus failure, const char* where, const Variables& best, int iterations) {
    if (st_.log) *st_.log << "stopped: " << where << "\n";
    v_ = best;
    residuals(v_, r_);
    const IpmStatus found = verdict(r_, reduced_);
    // The polished point may meet the strict tolerances, or at least the reduced ones with a
    // far more accurate x (the full form's stall: relative gap 1e-11, x only to 1e-5).
    if (found == IpmStatus::kOptimal) {
      if (IpmResult* res = polish_exit(v_, reduced_, iterations, true)) return *res;
    }
    return finish(found == IpmStatus::kMaxIterations ? failure : found, v_, iterations);
  }
  IpmResult& trouble(const char* where, int iterations) {
    return stop_early(IpmStatus::kNumericalTrouble, where, last_good_, iterations);
  }
  Variables last_good_;
  Tolerances strict_, reduced_;
  double work_ = 0.0, polish_work_ = 0.0, g_work_ = 0.0, residual_work_ = 0.0;
  double polish_wait_ = 0.0;      // the budget the next attempt needs
  bool polish_deferred_ = false;  // an attempt was skipped or cut short for its cost
  double best_score_ = std::numeric_limits<double>::infinity();
  int stalled_ = 0;
  void log_header() const {
    if (st_.log) log_ipm_header(*st_.log, n_, p_, m_, sp_.cones, kkt_.reduced_size(), kkt_.factor_nonzeros());
  }
  void log_iteration(int k, const Residuals& r, double mu, double step, double sigma) const {
    if (st_.log) log_ipm_iteration(*st_.log, k, r, v_.kappa / v_.tau, mu, step, sigma, kkt_.last_refinement_steps());
  }

  // Residuals and stopping measures, timed.
  void residuals(const Variables& v, Residuals& r) {
    PhaseScope phase(clock_, IpmPhase::kResiduals);
    work_ += residual_work_;
    compute_residuals(sp_, gmat_, *op_, eq_, v, r);
  }

  const ConicProblem* op_ = nullptr;
  IpmSettings st_;
  IpmClock* clock_ = nullptr;
  ConicProblem sp_;
  Equilibration eq_;
  std::unique_ptr<ConeProduct> cones_;
  ConstraintMatrix gmat_;
  KktSystem kkt_;
  std::unique_ptr<Polisher> polisher_;
  IpmResult result_;
  Variables polished_;
  Residuals polished_r_;
  bool is_polished_ = false;
  int n_ = 0, p_ = 0, m_ = 0;
  Eigen::VectorXd cbh_;  // [-c; b; h]: the tau column of the embedding
  Variables v_;
  Residuals r_;
  NtScaling w_;
  Eigen::VectorXd lambda_, x1_;  // x1_ = K^{-1} [-c; b; h]
  Eigen::VectorXd e_;            // the identity of K
  // Per-iteration buffers, sized once (and kept between solves of a workspace): on the
  // compressed form (14 cone rows) allocation, not arithmetic, was a tenth of a solve.
  Eigen::VectorXd trial_s_, trial_z_, bs_aff_, ll_, corr_, rc_, bs_, ds_, wbs_, rhs_, sol_;
  Direction aff_, cor_;
  double denom_ = 0.0;  // kappa/tau + ||W z1||^2, minus the kappa/tau part
};

bool Solver::initialize() {
  v_.resize(n_, p_, m_);
  kkt_.set_full_refinement(false);  // a heuristic start: the reduced system's accuracy will do
  cones_->identity_scaling(w_);
  if (!kkt_.factor(w_)) return false;
  Eigen::VectorXd& rhs = rhs_;
  Eigen::VectorXd& sol = sol_;
  rhs.resize(n_ + p_ + m_);
  // Primal start: min ||G x - h||^2 s.t. A x = b, s = h - G x shifted into K.
  rhs << Eigen::VectorXd::Zero(n_), sp_.b, sp_.h;
  if (!kkt_.solve(rhs, sol)) return false;
  v_.x = sol.head(n_);
  v_.s = -sol.tail(m_);
  // Dual start: min ||z||^2 s.t. A^T y + G^T z + c = 0, shifted into K.
  rhs.head(n_) = -sp_.c;
  rhs.tail(p_ + m_).setZero();
  if (!kkt_.solve(rhs, sol)) return false;
  v_.y = sol.segment(n_, p_);
  v_.z = sol.tail(m_);
  if (m_ > 0) {
    PhaseScope phase(clock_, IpmPhase::kCones);
    // Shifted into K with a margin relative to the shift: next to an entry of 1e18 (a large
    // finite bound) a shift of exactly 1 - e rounds the smallest entry to 0, on the boundary.
    const double es = cones_->min_eigenvalue(v_.s);
    if (es <= 0.0) cones_->add_identity(v_.s, (1.0 - es) * (1.0 + 1e-8));
    const double ez = cones_->min_eigenvalue(v_.z);
    if (ez <= 0.0) cones_->add_identity(v_.z, (1.0 - ez) * (1.0 + 1e-8));
  }
  v_.tau = 1.0;
  v_.kappa = 1.0;
  return v_.x.allFinite() && v_.y.allFinite() && v_.z.allFinite() && v_.s.allFinite();
}

bool Solver::direction(double sigma, const Eigen::VectorXd& bs, double rk, Direction& d, bool refine) {
  const double f = 1.0 - sigma;
  Eigen::VectorXd& wbs = wbs_;
  {
    PhaseScope phase(clock_, IpmPhase::kCones);
    cones_->apply_w(w_, bs, wbs);
  }
  Eigen::VectorXd& rhs = rhs_;
  Eigen::VectorXd& sol = sol_;
  rhs.resize(n_ + p_ + m_);
  rhs << f * r_.rx, -f * r_.ry, -f * r_.rz - wbs;
  if (!kkt_.solve(rhs, sol, refine)) return false;
  const double tau = v_.tau, kappa = v_.kappa;
  const double den = kappa / tau + denom_;
  d.dtau = (f * r_.rtau + rk / tau + cbh_.tail(p_ + m_).dot(sol.tail(p_ + m_)) + sp_.c.dot(sol.head(n_))) / den;
  d.dx.noalias() = sol.head(n_) + d.dtau * x1_.head(n_);
  d.dy.noalias() = sol.segment(n_, p_) + d.dtau * x1_.segment(n_, p_);
  d.dz.noalias() = sol.tail(m_) + d.dtau * x1_.tail(m_);
  {
    PhaseScope phase(clock_, IpmPhase::kCones);
    cones_->apply_w(w_, d.dz, d.dz_scaled);
  }
  d.ds_scaled.noalias() = bs - d.dz_scaled;
  d.dkappa = (rk - kappa * d.dtau) / tau;
  return std::isfinite(d.dtau) && d.dx.allFinite() && d.dz.allFinite() && d.ds_scaled.allFinite();
}

double Solver::max_step(const Direction& d) const {
  double a = std::numeric_limits<double>::infinity();
  if (m_ > 0) {
    PhaseScope phase(clock_, IpmPhase::kCones);
    a = std::min(a, cones_->max_step(lambda_, d.ds_scaled));
    a = std::min(a, cones_->max_step(lambda_, d.dz_scaled));
  }
  if (d.dtau < 0.0) a = std::min(a, -v_.tau / d.dtau);
  if (d.dkappa < 0.0) a = std::min(a, -v_.kappa / d.dkappa);
  return a;
}

IpmResult& Solver::finish(IpmStatus status, const Variables& v, int iterations) {
  IpmResult& res = result_;  // assigned in place: same sizes, same buffers as the last solve
  res.status = status;
  res.iterations = iterations;
  res.reduced_accuracy = false;
  res.note.clear();
  res.primal_residual_floor = res.dual_residual_floor = 0.0;
  double scale = v.tau;
  double yz_scale = v.tau;
  if (status == IpmStatus::kPrimalInfeasible) {
    yz_scale = -r_.hz_by;  // certificate normalized to h^T z + b^T y = -1
    scale = std::numeric_limits<double>::infinity();
  } else if (status == IpmStatus::kDualInfeasible) {
    scale = -r_.cx;  // certificate normalized to c^T x = -1
    yz_scale = std::numeric_limits<double>::infinity();
  }
  auto safe = [](double s) { return std::isfinite(s) && s > 0.0; };
  if (safe(scale)) {
    res.x = eq_.col.cwiseProduct(v.x) / scale;
    res.s = v.s.cwiseQuotient(eq_.row_cone) / scale;
  } else {
    res.x.setZero(n_);
    res.s.setZero(m_);
  }
  if (safe(yz_scale)) {
    res.y = eq_.row_eq.cwiseProduct(v.y) / yz_scale;
    res.z = eq_.row_cone.cwiseProduct(v.z) / yz_scale;
  } else {
    res.y.setZero(p_);
    res.z.setZero(m_);
  }
  res.polished = is_polished_;
  // The status is what the returned vectors certify on the given data (certificate.h).
  const ExitMeasures m = certify(*op_, st_, res);
  if (res.reduced_accuracy) {
    const ResidualFloors f = residual_floors(sp_, gmat_, *op_, eq_, v);
    res.primal_residual_floor = f.primal;
    res.dual_residual_floor = f.dual;
    res.note = shortfall(m, res.status, strict_, f.primal, f.dual);
  }
  res.kkt_factor_nonzeros = kkt_.factor_nonzeros();
  if (clock_) {
    clock_->timings().ipm_operations = ipm_work();
    clock_->timings().polish_operations = polish_work_;
  }
  res.polish_newton_steps = is_polished_ ? polisher_->last_newton_steps() : 0;
  return res;
}

IpmResult* Solver::polish_exit(const Variables& v, const Tolerances& t, int iterations, bool allow_reduced) {
  if (!st_.polish || !polisher_) return nullptr;  // (a workspace keeps the polisher of earlier solves)
  // All attempts together cost at most what the interior-point method has cost so far: a
  // rejected polish (a wrong active set, a system too large to pay off) is never the bulk of
  // a solve. The smallest attempt factors a dense system of n + p unknowns.
  // An attempt cut short for its cost waits until the budget has doubled: attempts cut
  // one after the other would each spend the budget and finish none.
  const double budget = ipm_work() - polish_work_;
  if (budget < polish_wait_) {
    polish_deferred_ = true;
    return nullptr;
  }
  {
    PhaseScope phase(clock_, IpmPhase::kPolish);
    if (clock_) ++clock_->timings().polish_attempts;
    // (less the residuals of the polished point, computed here)
    const bool ok = polisher_->polish(v, polished_, budget - residual_work_);
    polish_work_ += polisher_->last_work();
    if (polisher_->last_out_of_budget()) {
      polish_deferred_ = true;
      polish_wait_ = 2.0 * budget;
    }
    if (!ok) return nullptr;
    polish_work_ += residual_work_;
    compute_residuals(sp_, gmat_, *op_, eq_, polished_, polished_r_);
    if (verdict(polished_r_, t) != IpmStatus::kOptimal) return nullptr;
  }
  std::swap(r_, polished_r_);
  is_polished_ = true;
  IpmResult& res = finish(IpmStatus::kOptimal, polished_, iterations);
  const bool accepted = res.status == IpmStatus::kOptimal && (allow_reduced || !res.reduced_accuracy);
  if (st_.log) {
    char buf[200];
    std::snprintf(buf, sizeof buf, "polished (%d Newton steps): pres %.1e, dres %.1e, gap %.1e, objective gap %.1e%s\n",
                  polisher_->last_newton_steps(), res.primal_residual, res.dual_residual, res.gap, res.objective_gap,
                  accepted ? "" : ": rejected on the unscaled data");
    *st_.log << buf;
  }
  if (accepted) return &res;
  std::swap(r_, polished_r_);
  is_polished_ = false;
  return nullptr;
}

IpmResult& Solver::iterate() {
  log_header();
  if (!initialize()) {
    residuals(v_, r_);
    return finish(IpmStatus::kNumericalTrouble, v_, 0);
  }
  last_good_ = v_;
  double step = 0.0, sigma = 0.0;
  for (int k = 0;; ++k) {
    residuals(v_, r_);
    const double mu = (v_.s.dot(v_.z) + v_.tau * v_.kappa) / (cones_->degree() + 1);
    log_iteration(k, r_, mu, step, sigma);
    if (!std::isfinite(r_.primal_residual) || !std::isfinite(r_.dual_residual) || !std::isfinite(mu)) {
      return trouble("non-finite residuals", k);
    }
    const IpmStatus found = verdict(r_, strict_);
    // Converged while the polish waited for its budget: one more try, from the best iterate.
    if (found == IpmStatus::kOptimal && polish_deferred_) {
      if (IpmResult* res = polish_exit(v_, strict_, k, false)) return *res;
    }
    if (found != IpmStatus::kMaxIterations) return finish(found, v_, k);
    if (r_.primal_residual < st_.polish_from && r_.dual_residual < st_.polish_from &&
        std::min(r_.gap, r_.relative_gap) < st_.polish_from) {
      if (IpmResult* res = polish_exit(v_, strict_, k, false)) return *res;
    }
    // Keep the iterate closest to any verdict, for the reduced-accuracy exits.
    const double score = std::min({std::max({r_.primal_residual, r_.dual_residual, std::min(r_.gap, r_.relative_gap)}),
                                   r_.primal_infeasibility, r_.dual_infeasibility});
    if (score <= best_score_) {
      best_score_ = score;
      last_good_ = v_;
      stalled_ = 0;
    } else if (best_score_ < 1e-6 && ++stalled_ >= 3) {
      // Close to a verdict, three iterations without getting closer: rounding now dominates
      // (typically the refinement can no longer resolve the KKT system), stop with the best.
      // Far from convergence the measures may rise for a while (HSDE), so no test there.
      return trouble("no progress in 3 iterations", k);
    }
    if (k >= st_.max_iterations) return stop_early(IpmStatus::kMaxIterations, "iteration limit", last_good_, k);
    // The cones' scalings, products and steps, and an iteration's fixed cost (a few
    // microseconds: calls, loops over the cones, the direction's assembly).
    work_ += 3000.0 + 80.0 * m_ + 20.0 * (n_ + p_);
    kkt_.set_full_refinement(best_score_ < st_.full_refinement_from);

    {
      PhaseScope phase(clock_, IpmPhase::kCones);
      if (!cones_->compute_scaling(v_.s, v_.z, w_, lambda_)) return trouble("scaling", k);
    }
    if (!kkt_.factor(w_)) return trouble("factor", k);
    if (!kkt_.solve(cbh_, x1_)) return trouble("solve", k);
    // -[c; b; h]^T x1 = ||W z1||^2 > 0 (exactly, for the unregularized system).
    denom_ = -(sp_.c.dot(x1_.head(n_)) + cbh_.tail(p_ + m_).dot(x1_.tail(p_ + m_)));
    // Predictor (affine scaling): sigma = 0, target lambda o lambda -> 0.
    Direction& aff = aff_;
    Direction& cor = cor_;
    bs_aff_ = -lambda_;
    if (!direction(0.0, bs_aff_, -v_.kappa * v_.tau, aff, false)) return trouble("predictor", k);
    const double a_aff = std::min(1.0, max_step(aff));
    sigma = std::clamp(std::pow(1.0 - a_aff, 3), 1e-4, 1.0);
    // Corrector: centering sigma mu plus Mehrotra's second-order term.
    {
      PhaseScope phase(clock_, IpmPhase::kCones);
      cones_->jordan_product(lambda_, lambda_, ll_);
      cones_->jordan_product(aff.ds_scaled, aff.dz_scaled, corr_);
      rc_ = -ll_ + sigma * mu * e_ - corr_;
      cones_->jordan_divide(lambda_, rc_, bs_);
    }
    const double rk = -v_.kappa * v_.tau + sigma * mu - aff.dkappa * aff.dtau;
    if (!direction(sigma, bs_, rk, cor)) return trouble("corrector", k);
    step = std::min(1.0, st_.step_fraction * max_step(cor));
    Eigen::VectorXd& ds = ds_;
    {
      PhaseScope phase(clock_, IpmPhase::kCones);
      cones_->apply_w(w_, cor.ds_scaled, ds);
    }
    // Rounding can push s or z out of K by a hair near the boundary: back off if so.
    bool moved = false;
    for (int tries = 0; tries < 20 && step > 1e-12; ++tries, step *= 0.5) {
      const double tau = v_.tau + step * cor.dtau, kappa = v_.kappa + step * cor.dkappa;
      if (!(tau > 0.0 && kappa > 0.0)) continue;
      trial_s_ = v_.s + step * ds;
      trial_z_ = v_.z + step * cor.dz;
      {
        PhaseScope phase(clock_, IpmPhase::kCones);
        if (m_ > 0 && !(cones_->interior(trial_s_) && cones_->interior(trial_z_))) continue;
      }
      v_.x += step * cor.dx;
      v_.y += step * cor.dy;
      v_.s.swap(trial_s_);
      v_.z.swap(trial_z_);
      v_.tau = tau;
      v_.kappa = kappa;
      moved = true;
      break;
    }
    if (!moved) return trouble("step", k);
  }
}

}  // namespace

struct IpmWorkspace::State {
  Solver solver;
  InfiniteRows infinite_rows;  // the presolved problem, when rows were set aside
};

IpmWorkspace::IpmWorkspace() : state_(std::make_unique<State>()) {}
IpmWorkspace::~IpmWorkspace() = default;
IpmWorkspace::IpmWorkspace(IpmWorkspace&&) noexcept = default;
IpmWorkspace& IpmWorkspace::operator=(IpmWorkspace&&) noexcept = default;

namespace {

IpmResult& solve_with(const ConicProblem& problem, const IpmSettings& settings, IpmWorkspace::State& state) {
  IpmTimings timings;
  const IpmClock::Clock::time_point start = IpmClock::Clock::now();
  IpmClock clock(timings, settings.time_phases);
  bool presolved = false;
  {
    PhaseScope phase(&clock, IpmPhase::kValidation);
    validate(problem);
    presolved = remove_infinite_rows(problem, settings.infinity, state.infinite_rows);
  }
  IpmResult& r = state.solver.run(presolved ? state.infinite_rows.reduced : problem, settings, &clock);
  r.infinite_rows = 0;
  if (presolved) restore_infinite_rows(problem, state.infinite_rows, r);
  clock.enter(IpmPhase::kOther);  // charges the time since the last switch
  r.timings = timings;
  r.seconds = std::chrono::duration<double>(IpmClock::Clock::now() - start).count();
  return r;
}

}  // namespace

const IpmResult& solve_conic(const ConicProblem& problem, const IpmSettings& settings, IpmWorkspace& workspace) {
  return solve_with(problem, settings, *workspace.state_);
}

IpmResult solve_conic(const ConicProblem& problem, const IpmSettings& settings) {
  // A small problem is solved in this thread's buffers of the last small solve: allocating
  // the solver's hundred-odd vectors afresh was a tenth of its time. The results are the
  // same (IpmWorkspace); a large problem gets buffers of its own, freed on return.
  constexpr double kReuseBelow = 1e5;  // entries of A and G plus rows and columns
  const double entries = static_cast<double>(problem.A.nonZeros()) + static_cast<double>(problem.G.nonZeros()) +
                         static_cast<double>(problem.dense_G.size()) + problem.num_variables() +
                         problem.num_equalities() + problem.num_cone_rows();
  if (entries < kReuseBelow) {
    thread_local IpmWorkspace::State state;
    return solve_with(problem, settings, state);
  }
  IpmWorkspace::State state;
  return std::move(solve_with(problem, settings, state));
}

}  // namespace bivo::solvers::conic
