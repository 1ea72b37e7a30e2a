#pragma once
// The frames of a sequence in order, each decoded, checked and undistorted, for a tracker
// that takes them one at a time.
//
// Loading a frame costs more than tracking a pair (fr1/rpy: ~17 ms of PNG decoding and
// undistortion per frame against ~4.5 ms for a weighted pair at 320x240), and nothing in it
// depends on the tracking. With `loaders` >= 1 the stream loads on threads of its own, each
// frame on one of them, up to `loaders` frames ahead of the caller: with one, while the caller
// tracks pair k (frames k, k + 1), frame k + 2 is decoded and the thread then waits until it
// is taken; with two, frames k + 2 and k + 3 are decoded at once, so that loading keeps up
// with the tracker where one decoder alone could not. Frames are delivered in order whatever
// the loader that finished first. A run holds 2 + `loaders` frames, not the sequence.
// loaders = 0: each frame loads inside next(), on the calling thread.
//
//   FrameStream frames(seq.frames, begin, end, seq.intrinsics, seq.distortion, 2);
//   RgbdImage first = frames.next();  // throws what loading threw, in frame order
#include <atomic>
#include <condition_variable>
#include <exception>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "odometry/io/camera_intrinsics.h"
#include "odometry/io/lens_distortion.h"
#include "odometry/io/tum_dataset.h"
#include "odometry/io/vignetting.h"

namespace bivo::odometry::io {

class FrameStream {
 public:
  static constexpr int kMaxLoaders = 16;
  // Frames [begin, end) of `frames`, which must outlive the stream. Every frame after the
  // first must have the first one's size (load_rgbd_image's check); all have the fall-off
  // 1 - vignetting rho^2 divided out (vignetting.h: 0, none) and are undistorted with one map
  // of (K, distortion) at that size.
  FrameStream(const std::vector<AssociatedFrame>& frames, int begin, int end, const Intrinsics& K,
              const Distortion& distortion, int loaders, double vignetting = 0.0);
  // Stops the loader threads; frames they are decoding are finished first.
  ~FrameStream();
  FrameStream(const FrameStream&) = delete;
  FrameStream& operator=(const FrameStream&) = delete;

  // The next frame. Throws the bivo::Error its loading threw (naming the file and its list
  // line) when that frame is asked for: the frames before a bad one are delivered first.
  // Throws bivo::Error past the last frame.
  RgbdImage next();
  // Wall time the last next() kept the caller waiting: the whole load without loaders, what
  // they had not finished yet with them.
  double last_wait_seconds() const { return last_wait_seconds_; }
  // CPU time of the loader threads (0 without) as the process's CPU clock counts it: Linux
  // adds a thread other than the caller into that clock as of its last tick or switch, not
  // the load in progress (its own clock would count that, and the process's clock minus it
  // would under-report the caller's work by ~2 ms per 640x480 pair). So the process's CPU
  // time minus this is the time of every other thread. The loaders stay alive until the
  // stream is destroyed, so this reads after the last frame too.
  double loader_cpu_seconds() const;

 private:
  // A frame loaded ahead, or the error its loading threw.
  struct Loaded {
    std::optional<RgbdImage> image;
    std::exception_ptr error;
  };
  // decode + check against the first frame's size (0: none) + fall-off divided out + undistort with `map`, built at
  // the frame's size when empty (a map keeps buffers for its thread: one per loader).
  Loaded load(int index, int width, int height, std::optional<Undistortion>& map) const;
  void run(int loader);  // one loader thread
  void stop_loaders();   // ends and joins the loader threads (each finishes its frame first)

  const std::vector<AssociatedFrame>& frames_;
  const int begin_, end_;
  const Intrinsics K_;
  const Distortion distortion_;
  const double vignetting_;
  const int loaders_;
  std::optional<Undistortion> undistortion_;  // without loaders: built at the first frame's size
  double last_wait_seconds_ = 0.0;

  // Under mutex_: the first frame's size (0 before it), frames next() has returned, the next
  // frame a loader takes, the frames (or errors) loaded and not yet returned.
  std::mutex mutex_;
  std::condition_variable changed_;
  int width_ = 0, height_ = 0;
  int delivered_ = 0;
  int next_to_load_ = 0;
  std::map<int, Loaded> loaded_;
  bool failed_ = false;  // a load threw: no frame after it is taken
  bool stop_ = false;
  std::vector<std::thread> threads_;
  std::unique_ptr<std::atomic<long>[]> loader_tids_;  // Linux thread ids, once they run
  mutable std::vector<int> schedstat_fds_;            // their /proc schedstat, opened at the first read
};

}  // namespace bivo::odometry::io
