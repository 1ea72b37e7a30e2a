#pragma once
// One step of a frame stream, as track_sequence takes it: pair k (reference, current) is
// estimated while frame k + 2, the next pair's current frame, is prepared beside it (pyramid
// and statistics; run_beside in parallel_chunks.h). With problem.threads >= 2 a worker
// prepares the frame and then joins the estimate's per-pixel passes, so the preparation no
// longer sits between pairs; with one thread it follows the estimate (track_sequence then
// prepares each frame right before its pair instead, while that pyramid can stay in cache).
// Results are those of estimate_motion and prepare_frame, whatever the thread count.
//
//   PreparedFrame reference = prepare_frame(f0, K, ...), current = prepare_frame(f1, K, ...);
//   StreamStep step = estimate_motion_preparing_next(reference, current, prior, options, f2, K);
//   reference = std::move(current);  current = std::move(step.next);
#include <optional>

#include "odometry/tracker.h"

namespace bivo::odometry {

struct StreamStep {
  PairResult pair;
  PreparedFrame next;                 // empty without a next image
  double next_prepare_seconds = 0.0;  // wall time of next's preparation (beside the estimate)
};

// next_image is prepared with options' levels, threads and finest level; its statistics only
// when the method reads them (reads_frame_statistics).
StreamStep estimate_motion_preparing_next(const PreparedFrame& reference, const PreparedFrame& current,
                                          const Eigen::Isometry3d& initial, const TrackerOptions& options,
                                          std::optional<io::RgbdImage> next_image, const io::Intrinsics& K);

}  // namespace bivo::odometry
