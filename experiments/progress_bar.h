#pragma once
// A one-line progress bar with rate and ETA on stderr, drawn only when stderr is a terminal
// (isatty), so logs, pipes and tests never see it.
//
//   ProgressBar bar("fr1_rpy single", n);
//   for (int k = 0; k < n; ++k) { ...; bar.tick(); }
//   bar.finish();
#include <chrono>
#include <string>

namespace bivo::experiments {

class ProgressBar {
 public:
  // enabled: -1 = decide by isatty(stderr), 0 = never, 1 = always (tests of the format).
  ProgressBar(std::string label, int total, int enabled = -1);
  ~ProgressBar();
  void tick(int steps = 1);
  void finish();  // clears the line; idempotent
  bool enabled() const { return enabled_; }

  // The text of the bar for `done` of `total` after `elapsed_s` seconds, e.g.
  // "label [#####.....] 45/90  12.3 it/s  ETA 3.7s" (pure, for tests).
  static std::string format(const std::string& label, int done, int total, double elapsed_s, int width = 30);

 private:
  void draw();
  std::string label_;
  int total_ = 0, done_ = 0;
  bool enabled_ = false, finished_ = false;
  std::chrono::steady_clock::time_point start_, last_draw_;
};

}  // namespace bivo::experiments
