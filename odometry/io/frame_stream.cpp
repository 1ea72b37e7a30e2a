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
                         const Distortion& distortion, int loaders, double vignetting)
    : frames_(frames),
      begin_(begin),
      end_(end),
      K_(K),
      distortion_(distortion),
      vignetting_(vignetting),
      loaders_(loaders) {
  if (begin < 0 || end > static_cast<int>(frames.size()) || begin >= end) {
    throw Error("frame stream: frames [" + std::to_string(begin) + ", " + std::to_string(end) + ") of a sequence of " +
                std::to_string(frames.size()));
  }
  if (!(vignetting >= 0.0 && vignetting < 1.0)) {
    throw Error("frame stream: vignetting fall-off " + std::to_string(vignetting) + ", expected [0, 1)");
  }
  if (loaders < 0 || loaders > kMaxLoaders) {
    throw Error("frame stream: " + std::to_string(loaders) + " loader threads, expected 0.." +
                std::to_string(kMaxLoaders));
  }
  next_to_load_ = begin;
  loader_tids_ = std::make_unique<std::atomic<long>[]>(static_cast<std::size_t>(loaders));
  schedstat_fds_.assign(static_cast<std::size_t>(loaders), -1);
  try {
    for (int l = 0; l < loaders; ++l) threads_.emplace_back([this, l] { run(l); });
  } catch (...) {  // a thread could not start: no destructor will stop those that did
    stop_loaders();
    throw;
  }
}

FrameStream::~FrameStream() {
  for (const int fd : schedstat_fds_) {
    if (fd >= 0) close(fd);
  }
  stop_loaders();
}

void FrameStream::stop_loaders() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  changed_.notify_all();
  for (std::thread& t : threads_) t.join();
}

FrameStream::Loaded FrameStream::load(int index, int width, int height, std::optional<Undistortion>& map) const {
  Loaded out;
  try {
    RgbdImage image = load_rgbd_image(frames_[static_cast<std::size_t>(index)], width, height);
    divide_out_vignetting(image, vignetting_, K_);
    if (!map) map.emplace(K_, distortion_, image.width, image.height);
    map->apply(image);
    out.image = std::move(image);
  } catch (...) {
    out.error = std::current_exception();
  }
  return out;
}

void FrameStream::run(int loader) {
  loader_tids_[static_cast<std::size_t>(loader)] = static_cast<long>(syscall(SYS_gettid));
  std::optional<Undistortion> map;  // this thread's
  for (;;) {
    int index = 0, width = 0, height = 0;
    {
      // Up to loaders_ frames ahead of the caller; frames after the first once its size is
      // known (the others are checked against it).
      std::unique_lock<std::mutex> lock(mutex_);
      changed_.wait(lock, [this] {
        return stop_ || failed_ || next_to_load_ >= end_ ||
               (next_to_load_ - (begin_ + delivered_) < loaders_ && (next_to_load_ == begin_ || width_ > 0));
      });
      if (stop_ || failed_ || next_to_load_ >= end_) break;
      index = next_to_load_++;
      width = width_;
      height = height_;
    }
    Loaded frame = load(index, width, height, map);
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      if (index == begin_ && frame.image) {
        width_ = frame.image->width;
        height_ = frame.image->height;
      }
      if (frame.error) failed_ = true;
      loaded_.emplace(index, std::move(frame));
    }
    changed_.notify_all();
  }
  // Alive until the destructor, so that loader_cpu_seconds() can read this thread's clock.
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [this] { return stop_; });
}

double FrameStream::loader_cpu_seconds() const {
  double total = 0.0;
  for (int l = 0; l < loaders_; ++l) {
    const long tid = loader_tids_[static_cast<std::size_t>(l)];
    if (tid == 0) continue;  // not started yet
    // The first field of schedstat: the thread's sum_exec_runtime in ns, the value Linux adds
    // into the process's CPU clock for a thread other than the caller. Opened once; each
    // pread from offset 0 formats it anew (~1 us, against ~3.5 us to open and close it).
    const std::string path = "/proc/self/task/" + std::to_string(tid) + "/schedstat";
    int& fd = schedstat_fds_[static_cast<std::size_t>(l)];
    if (fd < 0) fd = open(path.c_str(), O_RDONLY | O_CLOEXEC);
    char text[128] = {};
    const ssize_t n = fd < 0 ? -1 : pread(fd, text, sizeof text - 1, 0);
    if (n <= 0) throw Error("frame stream: cannot read a loader thread's CPU time from " + path);
    total += 1e-9 * std::strtod(text, nullptr);
  }
  return total;
}

RgbdImage FrameStream::next() {
  const auto t0 = std::chrono::steady_clock::now();
  std::unique_lock<std::mutex> lock(mutex_);
  if (delivered_ >= end_ - begin_) {
    throw Error("frame stream: all " + std::to_string(end_ - begin_) + " frames were delivered");
  }
  const int index = begin_ + delivered_;
  RgbdImage image;
  if (loaders_ == 0) {
    Loaded frame = load(index, width_, height_, undistortion_);
    if (!frame.image) std::rethrow_exception(frame.error);
    if (index == begin_) {
      width_ = frame.image->width;
      height_ = frame.image->height;
    }
    image = std::move(*frame.image);
  } else {
    changed_.wait(lock, [&] { return loaded_.count(index) > 0; });
    const auto it = loaded_.find(index);
    if (!it->second.image) std::rethrow_exception(it->second.error);  // kept: asked again, thrown again
    image = std::move(*it->second.image);
    loaded_.erase(it);
  }
  ++delivered_;
  lock.unlock();
  changed_.notify_all();
  last_wait_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return image;
}

}  // namespace bivo::odometry::io
