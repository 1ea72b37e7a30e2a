#pragma once
// Phase timers: every layer records wall time per named phase into one PhaseProfile, so
// `bivo profile` can split a frame pair's time without timing code sprinkled around.
// Phase names used across the project (odometry: docs/odometry.md "Speed"):
//   "pyramid" (pyramid + statistics of a frame), "reference" (a level's pose-independent
//   data), "residuals" (the warp: residuals, image gradients, validity, F under the stored
//   weights), "weights" (robust scales), "normal_equations" (weights applied, Jacobians, H, b, a
//   in one pass), "cone_data", "subproblem", "other".
// A name "a/b" is a part of phase "a" (a backend's own split, e.g.
// "subproblem/ipm_kkt_factor"): total_seconds() leaves it out.
#include <chrono>
#include <map>
#include <string>

namespace bivo::solvers {

class PhaseProfile {
 public:
  void add(const std::string& phase, double seconds) { seconds_[phase] += seconds; }
  double seconds(const std::string& phase) const {
    const auto it = seconds_.find(phase);
    return it == seconds_.end() ? 0.0 : it->second;
  }
  double total_seconds() const {
    double s = 0.0;
    for (const auto& [name, t] : seconds_) {
      if (name.find('/') == std::string::npos) s += t;
    }
    return s;
  }
  const std::map<std::string, double>& all() const { return seconds_; }
  void merge(const PhaseProfile& other) {
    for (const auto& [name, t] : other.seconds_) seconds_[name] += t;
  }
  void clear() { seconds_.clear(); }

 private:
  std::map<std::string, double> seconds_;
};

// Adds the time from construction to destruction to `phase`; a null profile is a no-op.
class ScopedPhase {
 public:
  ScopedPhase(PhaseProfile* profile, const char* phase)
      : profile_(profile), phase_(phase), start_(std::chrono::steady_clock::now()) {}
  ~ScopedPhase() {
    if (profile_) {
      profile_->add(phase_, std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count());
    }
  }
  ScopedPhase(const ScopedPhase&) = delete;
  ScopedPhase& operator=(const ScopedPhase&) = delete;

 private:
  PhaseProfile* profile_;
  const char* phase_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace bivo::solvers
