#include "experiments/progress_bar.h"

#include <unistd.h>

#include <cstdio>
#include <iomanip>
#include <sstream>

namespace bivo::experiments {

ProgressBar::ProgressBar(std::string label, int total, int enabled)
    : label_(std::move(label)), total_(total), start_(std::chrono::steady_clock::now()), last_draw_(start_) {
  enabled_ = enabled < 0 ? ::isatty(STDERR_FILENO) != 0 : enabled != 0;
  if (enabled_) draw();
}

ProgressBar::~ProgressBar() { finish(); }

std::string ProgressBar::format(const std::string& label, int done, int total, double elapsed_s, int width) {
  std::ostringstream s;
  const double frac = total > 0 ? std::min(1.0, double(done) / total) : 0.0;
  const int filled = int(frac * width + 0.5);
  s << label << " [" << std::string(filled, '#') << std::string(width - filled, '.') << "] " << done << "/" << total;
  if (done > 0 && elapsed_s > 0) {
    const double rate = done / elapsed_s;
    s << std::fixed << std::setprecision(1) << "  " << rate << " it/s  ETA "
      << (total > done ? (total - done) / rate : 0.0) << "s";
  }
  return s.str();
}

void ProgressBar::tick(int steps) {
  done_ += steps;
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  // Redraw at most 10 times a second: a terminal write per frame would cost more than a pair.
  if (done_ >= total_ || now - last_draw_ > std::chrono::milliseconds(100)) {
    last_draw_ = now;
    draw();
  }
}

void ProgressBar::draw() {
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  std::fprintf(stderr, "\r\033[K%s", format(label_, done_, total_, elapsed).c_str());
  std::fflush(stderr);
}

void ProgressBar::finish() {
  if (!enabled_ || finished_) return;
  finished_ = true;
  std::fprintf(stderr, "\r\033[K");
  std::fflush(stderr);
}

}  // namespace bivo::experiments
