#include "odometry/io/trajectory.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "odometry/io/atomic_file.h"
#include "odometry/io/tum_text.h"
#include "solvers/error.h"

namespace bivo::odometry::io {

Trajectory read_tum_trajectory(const std::string& path) {
  Trajectory out;
  int previous_line = 0;
  for_each_tum_line(path, "trajectory", [&](const TumTextLine& l) {
    if (l.tokens.size() < 8) {
      throw Error(
          tum_line_error(path, l.line_no, "expected 'timestamp tx ty tz qx qy qz qw', got '" + excerpt(l.raw) + "'"));
    }
    if (l.tokens.size() > 8) {
      throw Error(tum_line_error(path, l.line_no, "unexpected extra field '" + excerpt(l.tokens[8]) + "'"));
    }
    double v[8];
    for (int i = 0; i < 8; ++i) v[i] = parse_tum_number(l.tokens[i], path, l.line_no, "a finite number");
    // Scaled by the largest component first: squaring components above ~1e154 overflows,
    // and normalize() of an infinite norm would silently give the identity.
    Eigen::Vector4d c(v[4], v[5], v[6], v[7]);
    const double largest = c.cwiseAbs().maxCoeff();
    if (!(largest > 0) || largest * (c / largest).norm() < 1e-6) {
      throw Error(tum_line_error(path, l.line_no, "quaternion has zero norm"));
    }
    c /= largest;
    const Eigen::Quaterniond q = Eigen::Quaterniond(c[3], c[0], c[1], c[2]).normalized();
    if (!out.empty() && v[0] <= out.back().timestamp) {
      if (v[0] < out.back().timestamp) {
        throw Error(tum_line_error(path, l.line_no,
                                   "timestamp " + excerpt(l.tokens[0]) + " is earlier than line " +
                                       std::to_string(previous_line) + "'s (list must be sorted)"));
      }
      // Real TUM ground truth holds such stamps (fr2/desk once, fr2/xyz 8 times): the later
      // pose holds, as in TUM's evaluate_rpe.py and evaluate_ate.py (a dict keyed by stamp).
      out.pop_back();
    }
    previous_line = l.line_no;
    StampedPose p;
    p.timestamp = v[0];
    p.T_wc.linear() = q.toRotationMatrix();
    p.T_wc.translation() = Eigen::Vector3d(v[1], v[2], v[3]);
    out.push_back(p);
  });
  if (out.empty()) throw Error("trajectory '" + path + "' has no poses");
  record_input(path);
  return out;
}

void write_tum_trajectory(std::ostream& o, const Trajectory& trajectory, const std::string& path) {
  o << "# timestamp tx ty tz qx qy qz qw (camera-to-world)\n";
  for (const auto& p : trajectory) {
    const Eigen::Vector3d t = p.T_wc.translation();
    Eigen::Quaterniond q(p.T_wc.linear());
    q.normalize();
    if (!std::isfinite(p.timestamp) || !t.allFinite() || !q.coeffs().allFinite()) {
      throw Error("refusing to write a non-finite pose at t=" + std::to_string(p.timestamp) + " to '" + path + "'");
    }
    o << std::fixed << std::setprecision(6) << p.timestamp << std::setprecision(9) << ' ' << t.x() << ' ' << t.y()
      << ' ' << t.z() << ' ' << q.x() << ' ' << q.y() << ' ' << q.z() << ' ' << q.w() << '\n';
  }
}

void write_tum_trajectory(const std::string& path, const Trajectory& trajectory) {
  write_file_atomically(path, [&](std::ostream& o) { write_tum_trajectory(o, trajectory, path); });
}

const StampedPose* nearest_pose(const Trajectory& trajectory, double t, double max_dt) {
  auto it = std::lower_bound(trajectory.begin(), trajectory.end(), t,
                             [](const StampedPose& p, double v) { return p.timestamp < v; });
  const StampedPose* best = nullptr;
  double best_dt = max_dt;
  if (it != trajectory.end() && std::abs(it->timestamp - t) <= best_dt) {
    best = &*it;
    best_dt = std::abs(it->timestamp - t);
  }
  if (it != trajectory.begin()) {
    const auto prev = std::prev(it);
    if (std::abs(prev->timestamp - t) <= best_dt) best = &*prev;
  }
  return best;
}

}  // namespace bivo::odometry::io
