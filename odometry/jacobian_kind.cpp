// JacobianKind's names (declared in rgbd_problem.h).
#include <string>

#include "odometry/rgbd_problem.h"
#include "solvers/error.h"

namespace bivo::odometry {

JacobianKind parse_jacobian_kind(const std::string& name) {
  if (name == "forward") return JacobianKind::kForward;
  if (name == "inverse") return JacobianKind::kInverse;
  if (name == "esm") return JacobianKind::kEsm;
  if (name == "auto") return JacobianKind::kMethodDefault;
  throw Error("unknown Jacobian kind '" + name + "' (valid: forward, inverse, esm, auto)");
}

const char* to_string(JacobianKind kind) {
  switch (kind) {
    case JacobianKind::kForward:
      return "forward";
    case JacobianKind::kInverse:
      return "inverse";
    case JacobianKind::kEsm:
      return "esm";
    case JacobianKind::kMethodDefault:
      return "auto";
  }
  return "?";
}

}  // namespace bivo::odometry
