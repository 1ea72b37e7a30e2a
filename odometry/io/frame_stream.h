#pragma once
// The frames of a sequence in order, each decoded, checked and undistorted, for a tracker
// that takes them one at a time.
//
// Loading a frame costs more than tracking a pair (fr1/rpy: ~16 ms of PNG decoding and
// undistortion per frame against ~4.5 ms for a weighted pair at 320x240), and nothing in it
// depends on the tracking. With `background` the stream loads on a thread of its own, one
// frame ahead of the caller: while the caller tracks pair k (frames k, k + 1), frame k + 2 is
// decoded, and the thread then waits until it is taken. A run holds three frames, not the
// sequence.
//
//   FrameStream frames(seq.frames, begin, end, seq.intrinsics, seq.distortion, true);
//   RgbdImage first = frames.next();  // throws what loading threw, in frame order
#include <atomic>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "odometry/io/camera_intrinsics.h"
#include "odometry/io/lens_distortion.h"
#include "odometry/io/tum_dataset.h"

namespace bivo::odometry::io {

class FrameStream {
 public:
  // Frames [begin, end) of `frames`, which must outlive the stream. Every frame after the
  // first must have the first one's size (load_rgbd_image's check); all are undistorted with
  // one map of (K, distortion) at that size.
  FrameStream(const std::vector<AssociatedFrame>& frames, int begin, int end, const Intrinsics& K,
              const Distortion& distortion, bool background);
  // Stops the loader thread; a frame it is decoding is finished first.
  ~FrameStream();
  FrameStream(const FrameStream&) = delete;
  FrameStream& operator=(const FrameStream&) = delete;

  // The next frame. Throws the bivo::Error its loading threw (naming the file and its list
  // line) when that frame is asked for: the frames before a bad one are delivered first.
  // Throws bivo::Error past the last frame.
  RgbdImage next();
  // Wall time the last next() kept the caller waiting: the whole load without background,
  // what the loader had not finished yet with it.
  double last_wait_seconds() const { return last_wait_seconds_; }
  // CPU time of the loader thread (0 without background) as the process's CPU clock counts
  // it: Linux adds a thread other than the caller into that clock as of its last tick or
  // switch, not the load in progress (its own clock would count that, and the process's
  // clock minus it would under-report the caller's work by ~2 ms per 640x480 pair). So the
  // process's CPU time minus this is the time of every other thread. The loader stays alive
  // until the stream is destroyed, so this reads after the last frame too.
  double loader_cpu_seconds() const;

 private:
  RgbdImage load(int index);  // decode + check + undistort (on the loader thread with background)
  void run();                 // the loader thread

  const std::vector<AssociatedFrame>& frames_;
  const int begin_, end_;
  const Intrinsics K_;
  const Distortion distortion_;
  const bool background_;
  int width_ = 0, height_ = 0;                // of the first frame (0 before it)
  std::optional<Undistortion> undistortion_;  // built at the first frame's size
  int delivered_ = 0;                         // frames next() has returned
  double last_wait_seconds_ = 0.0;

  // Loader thread state, under mutex_: one loaded frame waiting for the caller, or the
  // error of the frame after the last one delivered.
  std::mutex mutex_;
  std::condition_variable changed_;
  std::optional<RgbdImage> ready_;
  std::exception_ptr error_;
  bool stop_ = false;
  std::thread loader_;
  std::atomic<long> loader_tid_{0};  // the loader thread's Linux thread id, once it runs
  mutable int schedstat_fd_ = -1;    // its /proc schedstat, opened at the first read
};

}  // namespace bivo::odometry::io
