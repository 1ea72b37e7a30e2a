#pragma once
// Two consecutive real frames of ../shared (fr1/desk frames 2 and 3) prepared for the tracker,
// for tests that compare whole runs on real data; empty when the shared data are absent.
#include <filesystem>
#include <optional>
#include <string>

#include "odometry/tracker.h"

namespace bivo::testing {

struct RealPair {
  std::string folder;  // the sequence folder (named in the skip message when absent)
  std::optional<odometry::PreparedFrame> reference, current;
};

inline RealPair fr1_desk_pair(int levels) {
  RealPair p;
  p.folder = std::string(BIVO_SHARED_DIR) + "/data/tum/rgbd_dataset_freiburg1_desk";
  if (!std::filesystem::exists(p.folder)) return p;
  const odometry::io::TumSequence seq = odometry::io::open_tum_sequence(p.folder, {});
  const odometry::io::RgbdImage a = odometry::io::load_rgbd_image(seq.frames[2]);
  const odometry::io::RgbdImage b = odometry::io::load_rgbd_image(seq.frames[3], a.width, a.height);
  p.reference = odometry::prepare_frame(a, seq.intrinsics, levels);
  p.current = odometry::prepare_frame(b, seq.intrinsics, levels);
  return p;
}

}  // namespace bivo::testing
