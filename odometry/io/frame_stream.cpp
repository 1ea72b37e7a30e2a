#include "odometry/io/frame_stream.h"

#include <fcntl.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cstdlib>

#include <chrono>
#include <string>
#include <utility>

#include "solvers/error.h"

namespace bivo::odometry::io {

FrameStream::FrameStream(const std::vector<AssociatedFrame>& frames, int begin, int end, const Intrinsics& K,
                         const Distortion& distortion, bool background)
    : frames_(frames), begin_(begin), end_(end), K_(K), distortion_(distortion), background_(background) {
  if (begin < 0 || end > static_cast<int>(frames.size()) || begin >= end) {
    throw Error("frame stream: frames [" + std::to_string(begin) + ", " + std::to_string(end) + ") of a sequence of " +
                std::to_string(frames.size()));
  }
  if (!background_) return;
  loader_ = std::thread([this] { run(); });
}

FrameStream::~FrameStream() {
  if (schedstat_fd_ >= 0) close(schedstat_fd_);
  if (!loader_.joinable()) return;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  changed_.notify_all();
  loader_.join();
}

RgbdImage FrameStream::load(int index) {
  const AssociatedFrame& frame = frames_[static_cast<std::size_t>(index)];
  RgbdImage image = load_rgbd_image(frame, width_, height_);
  if (!undistortion_) {
    width_ = image.width;
    height_ = image.height;
    undistortion_.emplace(K_, distortion_, width_, height_);
  }
  undistortion_->apply(image);
  return image;
}

void FrameStream::run() {
  loader_tid_ = static_cast<long>(syscall(SYS_gettid));
  for (int k = begin_; k < end_; ++k) {
    {
      // One frame ahead: the next is loaded once the last one loaded has been taken.
      std::unique_lock<std::mutex> lock(mutex_);
      changed_.wait(lock, [this] { return stop_ || !ready_; });
      if (stop_) break;
    }
    std::optional<RgbdImage> image;
    std::exception_ptr error;
    try {
      image = load(k);
    } catch (...) {
      error = std::current_exception();
    }
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      ready_ = std::move(image);
      error_ = error;
    }
    changed_.notify_all();
    if (error) break;
  }
  // Alive until the destructor, so that loader_cpu_seconds() can read this thread's clock.
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [this] { return stop_; });
}

double FrameStream::loader_cpu_seconds() const {
  const long tid = loader_tid_;
  if (!background_ || tid == 0) return 0.0;  // no loader, or not started yet
  // The first field of schedstat: the thread's sum_exec_runtime in ns, the value Linux adds
  // into the process's CPU clock for a thread other than the caller. Opened once; each
  // pread from offset 0 formats it anew (~1 us, against ~3.5 us to open and close it).
  const std::string path = "/proc/self/task/" + std::to_string(tid) + "/schedstat";
  if (schedstat_fd_ < 0) schedstat_fd_ = open(path.c_str(), O_RDONLY | O_CLOEXEC);
  char text[128] = {};
  const ssize_t n = schedstat_fd_ < 0 ? -1 : pread(schedstat_fd_, text, sizeof text - 1, 0);
  if (n <= 0) throw Error("frame stream: cannot read the loader thread's CPU time from " + path);
  return 1e-9 * std::strtod(text, nullptr);
}

RgbdImage FrameStream::next() {
  if (delivered_ >= end_ - begin_) {
    throw Error("frame stream: all " + std::to_string(end_ - begin_) + " frames were delivered");
  }
  const auto t0 = std::chrono::steady_clock::now();
  RgbdImage image;
  if (!background_) {
    image = load(begin_ + delivered_);
  } else {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [this] { return ready_.has_value() || error_; });
    if (!ready_) std::rethrow_exception(error_);
    image = std::move(*ready_);
    ready_.reset();
    lock.unlock();
    changed_.notify_all();
  }
  ++delivered_;
  last_wait_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return image;
}

}  // namespace bivo::odometry::io
