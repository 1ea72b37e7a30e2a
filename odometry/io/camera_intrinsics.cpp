#include "odometry/io/camera_intrinsics.h"

#include <cmath>
#include <sstream>

#include "solvers/error.h"

namespace bivo::odometry::io {

Intrinsics Intrinsics::at_level(int level) const {
  Intrinsics k = *this;
  for (int l = 0; l < level; ++l) {
    k.fx *= 0.5;
    k.fy *= 0.5;
    k.cx = (k.cx + 0.5) * 0.5 - 0.5;
    k.cy = (k.cy + 0.5) * 0.5 - 0.5;
  }
  return k;
}

Intrinsics intrinsics_for_sequence(const std::string& name_or_path) {
  const auto has = [&](const char* s) { return name_or_path.find(s) != std::string::npos; };
  // Values from the TUM RGB-D benchmark's camera calibration page (ROS default for
  // unknown cameras).
  if (has("freiburg1") || has("fr1")) return {517.3, 516.5, 318.6, 255.3};
  if (has("freiburg2") || has("fr2")) return {520.9, 521.0, 325.1, 249.7};
  if (has("freiburg3") || has("fr3")) return {535.4, 539.2, 320.1, 247.6};
  return {525.0, 525.0, 319.5, 239.5};
}

Intrinsics parse_intrinsics(const std::string& text) {
  std::istringstream s(text);
  double v[4];
  for (double& x : v) {
    if (!(s >> x) || !std::isfinite(x)) {
      throw Error("intrinsics '" + text + "': expected four numbers 'fx fy cx cy'");
    }
  }
  std::string extra;
  if (s >> extra) throw Error("intrinsics '" + text + "': unexpected extra field '" + extra + "'");
  if (v[0] <= 0 || v[1] <= 0) throw Error("intrinsics '" + text + "': focal lengths must be positive");
  return {v[0], v[1], v[2], v[3]};
}

}  // namespace bivo::odometry::io
