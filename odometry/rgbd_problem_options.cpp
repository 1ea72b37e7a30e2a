#include <cmath>
#include <string>

#include "odometry/rgbd_problem.h"
#include "solvers/error.h"

namespace bivo::odometry {

void check_problem_options(const RgbdProblemOptions& o) {
  if (!(o.min_depth > 0.0) || !(o.max_depth > o.min_depth)) {
    throw Error("RGB-D problem: depth range [" + std::to_string(o.min_depth) + ", " + std::to_string(o.max_depth) +
                "] is empty or not positive");
  }
  if (o.threads < 1) throw Error("RGB-D problem: threads must be >= 1, got " + std::to_string(o.threads));
  if (o.depth_noise_exponent < 0 || o.depth_noise_exponent > 3) {
    throw Error(
        "RGB-D problem: depth noise exponent must be 0, 1, 2 or 3 (-1 'auto': resolve it first, "
        "method_depth_noise_exponent()), got " +
        std::to_string(o.depth_noise_exponent));
  }
  if (!(o.radial_prior >= 0.0) || !std::isfinite(o.radial_prior)) {
    throw Error("RGB-D problem: radial prior must be finite and >= 0, got " + std::to_string(o.radial_prior));
  }
  if (o.affine_brightness < 0 || o.affine_brightness > 2) {
    throw Error("RGB-D problem: affine brightness must be 0, 1 or 2 (-1 'auto': resolve it first), got " +
                std::to_string(o.affine_brightness));
  }
  if (o.jacobian == JacobianKind::kMethodDefault) {
    throw Error("RGB-D problem: Jacobian kind 'auto' names a method's default; resolve it first (method_jacobian())");
  }
}

}  // namespace bivo::odometry
