#pragma once
// Pinhole intrinsics, the TUM presets chosen by sequence name, and their scaling to
// pyramid levels.
#include <string>

namespace bivo::odometry::io {

struct Intrinsics {
  double fx = 525.0, fy = 525.0, cx = 319.5, cy = 239.5;

  // Intrinsics of pyramid level `level` (0 = full resolution) built by 2x2 averaging: a
  // coarse pixel centre lies at the centre of its 2x2 block, x_c = (x_f - 0.5) / 2, so
  // f' = f / 2 and c' = (c + 0.5) / 2 - 0.5 per level.
  Intrinsics at_level(int level) const;
};

// TUM presets by the sequence name (or any path containing it): "freiburg1", "freiburg2",
// "freiburg3" (also "fr1"... ), otherwise the TUM default 525 525 319.5 239.5.
Intrinsics intrinsics_for_sequence(const std::string& name_or_path);

// Parses "fx fy cx cy" (the --intrinsics override); throws bivo::Error naming the text on
// anything but four finite numbers with fx, fy > 0.
Intrinsics parse_intrinsics(const std::string& text);

}  // namespace bivo::odometry::io
