#include "solvers/conic/kkt_system.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

extern "C" {
#include <camd.h>
#include <ldl.h>
}

#include "solvers/error.h"

namespace bivo::solvers::conic {

// q-hat = q1 / ||q1|| of a cone's scaling, or 0 when q1 = 0 (then c+ = c- = 0 and the
// expansion columns decouple; any unit vector would do).
static bool has_direction(const SocScaling& sc, int dim) {
  return dim > 1 && sc.q1_norm > 0.0 && sc.wb.tail(dim - 1).norm() > 0.0;
}

KktSystem::KktSystem(const SparseMatrix& A, const ConstraintMatrix& Gm, const ConeProduct& cones, KktSettings settings,
                     IpmClock* clock) {
  setup(A, Gm, cones, settings, clock);
}

// A z pivot -w_i^2 or -beta_k^2 below the dynamic threshold is replaced by
// -dynamic_regularization, as the sparse LDL of the unreduced matrix would do: otherwise
// D^-1 ~ 1e18 swamps the x block (s -> 0 on an unbounded ray) and the refinement diverges.
double KktSystem::z_pivot(double d) {
  if (d > settings_.dynamic_threshold) return d;
  ++dynamic_pivots_;
  z_regularized_ = true;
  return settings_.dynamic_regularization;
}

bool KktSystem::factor(const NtScaling& w) {
  PhaseScope phase(clock_, IpmPhase::kKktFactor);
  if (clock_) ++clock_->timings().kkt_factors;
  work_ += factor_work_ + 3.0 * static_cast<double>(Kx_.size()) + g_work_ + 4.0 * m_;
  w_ = w;
  dynamic_pivots_ = 0;
  z_regularized_ = false;
  const int l = cones_->spec().nonnegative;
  for (int r = 0; r < l; ++r) inv_d_[r] = 1.0 / z_pivot(w.orthant_w[r] * w.orthant_w[r]);
  Kx_ = base_;
  for (std::size_t e = 0; e < orth_slot_.size(); ++e) Kx_[orth_slot_[e]] += orth_val_[e] * inv_d_[orth_row_[e]];
  inv_b2_.resize(nsoc_);
  for (int k = 0; k < nsoc_; ++k) {
    const SocScaling& sc = w.soc[k];
    const int o = cones_->soc_offset(k), d = cones_->spec().soc[k];
    const double b2 = sc.beta * sc.beta, pivot = z_pivot(b2);
    inv_b2_[k] = 1.0 / pivot;
    for (int i = 0; i < d; ++i) inv_d_[o + i] = inv_b2_[k];
    const bool unit = has_direction(sc, d);
    if (unit) {
      qhat_.segment(o + 1, d - 1) = sc.wb.tail(d - 1) / sc.wb.tail(d - 1).norm();
    } else if (d > 1) {
      qhat_.segment(o + 1, d - 1).setZero();
    }
    // V = beta sqrt(c-) g, U = beta sqrt(c+) f with g = (1, -qh), f = (1, qh): the couplings
    // G^T D^-1 V = beta sqrt(c-) / pivot G^T g; the pivots -1 + c- ||g||^2 beta^2 / pivot and
    // 1 + c+ ||f||^2 beta^2 / pivot, i.e. -(q0 - ||q1||)^2 and (q0 + ||q1||)^2 when
    // ||qh|| = 1 and the pivot is beta^2, written so without cancellation.
    scale_p_[k] = sc.beta * std::sqrt(sc.cminus) * inv_b2_[k];
    scale_q_[k] = sc.beta * std::sqrt(sc.cplus) * inv_b2_[k];
    const double sum = sc.q0 + sc.q1_norm, norm2 = unit ? 2.0 : 1.0;
    if (unit && pivot == b2) {
      Kx_[p_diag_[k]] = -1.0 / (sum * sum);
      Kx_[q_diag_[k]] = sum * sum;
    } else {
      Kx_[p_diag_[k]] = -1.0 + sc.cminus * norm2 * b2 * inv_b2_[k];
      Kx_[q_diag_[k]] = 1.0 + sc.cplus * norm2 * b2 * inv_b2_[k];
    }
  }
  for (std::size_t e = 0; e < soc_slot_.size(); ++e) Kx_[soc_slot_[e]] += soc_val_[e] * inv_b2_[soc_cone_[e]];
  // G_k,tail^T q-hat for every coupled column, one pass over G's nonzeros.
  // Column by column, accumulating in a register while the target stays the same (a cone's
  // rows are contiguous), so no store-to-load chain through gq_.
  gq_.setZero();
  if (G_->dense()) {
    for (int k = 0; k < nsoc_; ++k) {
      const int o = cones_->soc_offset(k), d = cones_->spec().soc[k];
      if (d < 2 || !has_direction(w.soc[k], d)) continue;  // q-hat = 0 (e.g. W = I): G^T q-hat = 0
      gq_full_.setZero(n_);
      G_->add_rows_multiply_transpose(o + 1, d - 1, 1.0, qhat_.segment(o + 1, d - 1), gq_full_);
      for (int c = couple_begin_[k]; c < couple_begin_[k + 1]; ++c) gq_[c] = gq_full_[couple_col_[c]];
    }
  } else {
    const SparseMatrix& G = G_->sparse();
    const int* outer = G.outerIndexPtr();
    const int* inner = G.innerIndexPtr();
    const double* val = G.valuePtr();
    for (int j = 0; j < G.outerSize(); ++j) {
      int target = -1;
      double acc = 0.0;
      for (int e = outer[j]; e < outer[j + 1]; ++e) {
        if (gq_target_[e] != target) {
          if (target >= 0) gq_[target] += acc;
          target = gq_target_[e];
          acc = 0.0;
        }
        acc += val[e] * qhat_[inner[e]];
      }
      if (target >= 0) gq_[target] += acc;
    }
  }
  for (int k = 0; k < nsoc_; ++k) {
    for (int c = couple_begin_[k]; c < couple_begin_[k + 1]; ++c) {
      Kx_[couple_p_slot_[c]] = scale_p_[k] * (head_row_[c] - gq_[c]);
      Kx_[couple_q_slot_[c]] = scale_q_[k] * (head_row_[c] + gq_[c]);
    }
  }
  for (int j = 0; j < R_; ++j) {
    for (int s = Kp_[j]; s < Kp_[j + 1]; ++s) {
      if (Ki_[s] > j) Kx_[s] = Kx_[mirror_[s]];
    }
  }
  return numeric_with_dynamic_regularization();
}

// Up-looking LDL^T (row k of L from a sparse triangular solve along the elimination tree
// computed by ldl_symbolic), the algorithm of SuiteSparse LDL plus the one thing it lacks:
// dynamic regularization as in ECOS. A quasi-definite matrix has known pivot signs (x and q
// positive; y and p negative); a pivot that rounding has driven to zero or to the wrong
// sign (W^{-2} ~ 1e16 swamps delta in the x block near the end) is replaced by
// sign * dynamic_regularization, and iterative refinement against the true matrix repairs
// the perturbation.
bool KktSystem::numeric_with_dynamic_regularization() {
  const int n = R_;
  for (int k = 0; k < n; ++k) {
    Y_[k] = 0.0;
    int top = n;
    Flag_[k] = k;
    Lnz_[k] = 0;
    const int kk = P_[k];
    for (int q = Kp_[kk]; q < Kp_[kk + 1]; ++q) {
      int i = Pinv_[Ki_[q]];
      if (i > k) continue;  // upper triangle of the permuted matrix only
      Y_[i] += Kx_[q];
      int len = 0;
      for (; Flag_[i] != k; i = Parent_[i]) {
        Pattern_[len++] = i;
        Flag_[i] = k;
      }
      while (len > 0) Pattern_[--top] = Pattern_[--len];
    }
    double dk = Y_[k];
    Y_[k] = 0.0;
    for (; top < n; ++top) {
      const int i = Pattern_[top];
      const double yi = Y_[i];
      Y_[i] = 0.0;
      const int end = Lp_[i] + Lnz_[i];
      for (int q = Lp_[i]; q < end; ++q) Y_[Li_[q]] -= Lx_[q] * yi;
      const double lki = yi / D_[i];
      dk -= lki * yi;
      Li_[end] = k;
      Lx_[end] = lki;
      ++Lnz_[i];
    }
    const double sign = sign_[kk];
    if (!(sign * dk > settings_.dynamic_threshold)) {
      if (!std::isfinite(dk)) return false;
      dk = sign * settings_.dynamic_regularization;
      ++dynamic_pivots_;
    }
    D_[k] = dk;
  }
  return true;
}

// z eliminated: dz = D^-1 (G dx + V dp + U dq - rz); the reduced right-hand side is
// [rx + G^T D^-1 rz; ry; V^T D^-1 rz; U^T D^-1 rz].
void KktSystem::reduced_rhs(const Eigen::VectorXd& r, Eigen::VectorXd& red) {
  const int pk0 = n_ + p_;
  red.resize(R_);
  // A zero z part (the initial dual start's right-hand side) needs no pass over G.
  work_ += R_ + 2.0 * m_;
  if (m_ > 0 && !r.tail(m_).isZero(0.0)) {
    work_ += g_work_;
    tz_ = r.tail(m_).cwiseProduct(Eigen::Map<const Eigen::VectorXd>(inv_d_.data(), m_));
    G_->multiply_transpose(tz_, red.head(n_));
    red.head(n_) += r.head(n_);
  } else {
    red.head(n_) = r.head(n_);
  }
  red.segment(n_, p_) = r.segment(n_, p_);
  for (int k = 0; k < nsoc_; ++k) {
    const int o = cones_->soc_offset(k), d = cones_->spec().soc[k];
    const double head = r[n_ + p_ + o];
    const double cross = d > 1 ? qhat_.segment(o + 1, d - 1).dot(r.segment(n_ + p_ + o + 1, d - 1)) : 0.0;
    red[pk0 + 2 * k] = scale_p_[k] * (head - cross);
    red[pk0 + 2 * k + 1] = scale_q_[k] * (head + cross);
  }
}

void KktSystem::ldl_solve(Eigen::VectorXd& red) {
  work_ += 4.0 * factor_nonzeros() + 3.0 * R_;
  ldl_perm(R_, red_perm_.data(), red.data(), P_.data());
  ldl_lsolve(R_, red_perm_.data(), Lp_.data(), Li_.data(), Lx_.data());
  ldl_dsolve(R_, red_perm_.data(), D_.data());
  ldl_ltsolve(R_, red_perm_.data(), Lp_.data(), Li_.data(), Lx_.data());
  ldl_permt(R_, red.data(), red_perm_.data(), P_.data());
}

void KktSystem::back_substitute(const Eigen::VectorXd& r, const Eigen::VectorXd& red, Eigen::VectorXd& sol) {
  const int pk0 = n_ + p_;
  sol.resize(n_ + p_ + m_);
  sol.head(n_ + p_) = red.head(n_ + p_);
  if (m_ == 0) return;
  work_ += g_work_ + 4.0 * m_;
  auto dz = sol.tail(m_);
  G_->multiply(red.head(n_), dz);
  dz -= r.tail(m_);
  for (int k = 0; k < nsoc_; ++k) {
    const int o = cones_->soc_offset(k), d = cones_->spec().soc[k];
    const double a = scale_p_[k] * red[pk0 + 2 * k], b = scale_q_[k] * red[pk0 + 2 * k + 1];
    // V dp + U dq = (a g + b f) * pivot; dz below gets D^-1 = 1/pivot.
    const double beta2 = 1.0 / inv_d_[o];
    dz[o] += beta2 * (a + b);
    if (d > 1) dz.segment(o + 1, d - 1) += (beta2 * (b - a)) * qhat_.segment(o + 1, d - 1);
  }
  dz = dz.cwiseProduct(Eigen::Map<const Eigen::VectorXd>(inv_d_.data(), m_));
}

void KktSystem::reduced_solve(const Eigen::VectorXd& r, Eigen::VectorXd& sol) {
  PhaseScope phase(clock_, IpmPhase::kKktSolve);
  reduced_rhs(r, red_);
  ldl_solve(red_);
  back_substitute(r, red_, sol);
}

// rhs - K v for the reduced matrix without the static regularization (+delta on x, -delta
// on y), i.e. the exact Schur complement of the unexpanded system's z block.
void KktSystem::reduced_residual(const Eigen::VectorXd& rhs, const Eigen::VectorXd& v, Eigen::VectorXd& out) {
  PhaseScope phase(clock_, IpmPhase::kRefinement);
  work_ += 2.0 * static_cast<double>(Kx_.size()) + 4.0 * R_;
  out = rhs;
  for (int j = 0; j < R_; ++j) {
    const double vj = v[j];
    for (int q = Kp_[j]; q < Kp_[j + 1]; ++q) out[Ki_[q]] -= Kx_[q] * vj;
  }
  const double delta = settings_.static_regularization;
  out.head(n_) += delta * v.head(n_);
  out.segment(n_, p_) -= delta * v.segment(n_, p_);
}

// rhs - K v for the unregularized, unexpanded K.
void KktSystem::residual(const Eigen::VectorXd& rhs, const Eigen::VectorXd& v, Eigen::VectorXd& out) {
  PhaseScope phase(clock_, IpmPhase::kRefinement);
  const int nr = n_ + p_ + m_;
  work_ += 2.0 * g_work_ + 4.0 * static_cast<double>(A_->nonZeros()) + 6.0 * m_ + nr;
  out.resize(nr);
  const double* vz = v.data() + n_ + p_;
  double* oz = out.data() + n_ + p_;
  out.head(n_) = rhs.head(n_);
  if (p_ > 0) {
    out.head(n_).noalias() -= A_->transpose() * v.segment(n_, p_);
    out.segment(n_, p_).noalias() = rhs.segment(n_, p_) - *A_ * v.head(n_);
  }
  if (m_ > 0) {
    G_->add_multiply_transpose(-1.0, v.tail(m_), out.head(n_));
    out.tail(m_) = rhs.tail(m_);
    G_->add_multiply(-1.0, v.head(n_), out.tail(m_));
  }
  const int l = cones_->spec().nonnegative;
  for (int r = 0; r < l; ++r) oz[r] += w_.orthant_w[r] * w_.orthant_w[r] * vz[r];
  for (int k = 0; k < nsoc_; ++k) {
    // W^2 x = beta^2 (2 q (q^T x) - J x), q = (q0, 2 wb0 wb1)
    const SocScaling& sc = w_.soc[k];
    const int o = cones_->soc_offset(k), d = cones_->spec().soc[k];
    const double two_wb0 = 2.0 * sc.wb[0];
    const double* wb = sc.wb.data();
    double t = 0.0;
    for (int i = 1; i < d; ++i) t += wb[i] * vz[o + i];
    t = 2.0 * (sc.q0 * vz[o] + two_wb0 * t);
    const double b2 = sc.beta * sc.beta;
    oz[o] += b2 * (t * sc.q0 - vz[o]);
    const double f = b2 * t * two_wb0;
    for (int i = 1; i < d; ++i) oz[o + i] += f * wb[i] + b2 * vz[o + i];
  }
}

bool KktSystem::solve(const Eigen::VectorXd& rhs, Eigen::VectorXd& sol, bool refine) {
  PhaseScope phase(clock_, IpmPhase::kKktSolve);
  if (clock_) ++clock_->timings().kkt_solves;
  last_refine_ = 0;
  if (!refine || z_regularized_) {
    reduced_solve(rhs, sol);
    if (!refine) return sol.allFinite();
    return refine_full(rhs, sol);
  }
  // Without a regularized z pivot the reduced system is exactly the unexpanded one with z
  // eliminated, so refinement runs on it (O(nnz) of the small reduced matrix per step, no
  // pass over G): it removes the static and the dynamic regularization of the factors.
  reduced_rhs(rhs, red_rhs_);
  red_ = red_rhs_;
  ldl_solve(red_);
  const double target = settings_.refinement_tolerance * (1.0 + red_rhs_.lpNorm<Eigen::Infinity>());
  double last_norm = std::numeric_limits<double>::infinity();
  for (int step = 1; step <= settings_.max_refinement_steps + 1; ++step) {
    reduced_residual(red_rhs_, red_, red_res_);
    const double norm = red_res_.lpNorm<Eigen::Infinity>();
    if (!std::isfinite(norm)) return false;
    if (norm >= last_norm) {  // stalled: go back to the better iterate
      red_ = red_best_;
      break;
    }
    last_norm = norm;
    if (norm <= target || step > settings_.max_refinement_steps) break;
    red_best_ = red_;
    if (clock_) ++clock_->timings().refinement_steps;
    ldl_solve(red_res_);
    red_ += red_res_;
    last_refine_ = step;
  }
  back_substitute(rhs, red_, sol);
  if (!full_refinement_) return sol.allFinite();
  return refine_full(rhs, sol);
}

// Refinement against the unregularized, unexpanded K (a pass over G per residual): when a z
// pivot was regularized the reduced system is not the true one.
bool KktSystem::refine_full(const Eigen::VectorXd& rhs, Eigen::VectorXd& sol) {
  const double target = settings_.refinement_tolerance * (1.0 + rhs.lpNorm<Eigen::Infinity>());
  residual(rhs, sol, res_);
  double last_norm = res_.lpNorm<Eigen::Infinity>();
  if (!std::isfinite(last_norm)) return false;
  for (int step = 1; step <= settings_.max_refinement_steps && last_norm > target; ++step) {
    if (clock_) ++clock_->timings().refinement_steps;
    reduced_solve(res_, cand_);
    cand_ += sol;
    residual(rhs, cand_, new_res_);
    const double norm = new_res_.lpNorm<Eigen::Infinity>();
    if (!std::isfinite(norm) || norm >= last_norm) break;  // stalled: keep the better iterate
    sol.swap(cand_);
    res_.swap(new_res_);
    last_norm = norm;
    last_refine_ = step;
  }
  return sol.allFinite();
}

}  // namespace bivo::solvers::conic
