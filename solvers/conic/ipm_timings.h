#pragma once
// Where the time of one solve_conic goes, phase by phase. Phases are exclusive: a clock
// switches from phase to phase (a nested phase pauses the enclosing one and gives it back on
// exit), so the phases sum to the solve's time up to the clock reads (~20 ns each). The
// products with G and G^T are their own phase wherever they run (residuals, KKT solves,
// refinement), except inside the polish, which is timed as a whole.
#include <array>
#include <chrono>
#include <string>
#include <utility>

#include "solvers/profiling.h"

namespace bivo::solvers::conic {

enum class IpmPhase : int {
  // Set-up, once per solve.
  kValidation,     // sizes, cone sums, finite entries
  kEquilibration,  // Ruiz factors and the scaled copy of the data
  kKktSetup,       // the KKT pattern and the per-cone Gram matrices
  kOrdering,       // CAMD
  kSymbolic,       // ldl_symbolic (elimination tree, column counts)
  // Per iteration (and the two initial solves).
  kResiduals,   // embedding residuals and stopping measures, without their G products
  kGPasses,     // products with G and G^T
  kKktFactor,   // numeric LDL^T (and the per-factorization cone terms), without G products
  kKktSolve,    // triangular solves and the z elimination, without G products
  kRefinement,  // residuals of the unexpanded KKT system, without G products
  kCones,       // NT scaling, Jordan products and divisions, W products, steps to the boundary
  kPolish,      // the active-set Newton polish, its G products included
  kOther,       // the rest: direction assembly, the iterate update, logging
  kCount
};

const char* to_string(IpmPhase phase);

struct IpmTimings {
  std::array<double, static_cast<int>(IpmPhase::kCount)> seconds{};
  int g_passes = 0;  // products with G or G^T (polish excluded)
  int kkt_factors = 0, kkt_solves = 0, refinement_steps = 0;
  int polish_attempts = 0;
  int kkt_setups = 0;  // pattern, ordering and symbolic factorization: once per solve
  // Operations counted from the patterns (KktSystem::work): the interior-point method's
  // (set-up and iterations) and the polish's, which never exceeds the former.
  double ipm_operations = 0.0, polish_operations = 0.0;

  IpmTimings& operator+=(const IpmTimings& o);  // phases and counters summed
  double& operator[](IpmPhase p) { return seconds[static_cast<int>(p)]; }
  double operator[](IpmPhase p) const { return seconds[static_cast<int>(p)]; }
  double setup_seconds() const;      // validation .. symbolic
  double iteration_seconds() const;  // residuals .. other, polish excluded
  double total_seconds() const;
  // One line per phase: "name  ms  share", plus the counters.
  std::string text(int iterations) const;
};

// Adds the phases to `profile` (null: no-op) as "subproblem/ipm_<phase>": parts of the outer
// loop's "subproblem" phase, for `bivo profile`.
void record_phases(const IpmTimings& timings, PhaseProfile* profile);

// The clock: enter(phase) charges the time since the last switch to the current phase.
// Untimed, it follows the phases, keeps the counters and times the polish alone (two reads
// per attempt, so its cost next to the iterations is always known): a solve of a small
// problem switches phase a few hundred times, and timing every switch was a tenth of it.
class IpmClock {
 public:
  using Clock = std::chrono::steady_clock;
  explicit IpmClock(IpmTimings& t, bool timed = true) : t_(t), timed_(timed), last_(Clock::now()) {}
  IpmPhase current() const { return current_; }
  bool timed() const { return timed_; }
  IpmPhase enter(IpmPhase p) {
    const bool charge = timed_ || current_ == IpmPhase::kPolish;
    if (!charge && p != IpmPhase::kPolish) return std::exchange(current_, p);
    const Clock::time_point now = Clock::now();
    if (charge) t_[current_] += std::chrono::duration<double>(now - last_).count();
    last_ = now;
    const IpmPhase previous = current_;
    current_ = p;
    return previous;
  }
  IpmTimings& timings() { return t_; }

 private:
  IpmTimings& t_;
  bool timed_;
  IpmPhase current_ = IpmPhase::kOther;
  Clock::time_point last_;
};

// Runs a scope in `phase` (a null clock, or a clock inside the polish, is left alone).
class PhaseScope {
 public:
  PhaseScope(IpmClock* clock, IpmPhase phase) : clock_(clock) {
    if (clock_ && clock_->current() == IpmPhase::kPolish && phase != IpmPhase::kPolish) clock_ = nullptr;
    if (clock_) previous_ = clock_->enter(phase);
  }
  ~PhaseScope() {
    if (clock_) clock_->enter(previous_);
  }
  bool active() const { return clock_ != nullptr; }
  PhaseScope(const PhaseScope&) = delete;
  PhaseScope& operator=(const PhaseScope&) = delete;

 private:
  IpmClock* clock_;
  IpmPhase previous_ = IpmPhase::kOther;
};

}  // namespace bivo::solvers::conic
