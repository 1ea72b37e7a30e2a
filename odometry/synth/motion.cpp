#include "odometry/synth/motion.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include "odometry/io/input_limits.h"
#include "odometry/synth/random.h"
#include "solvers/error.h"
#include "solvers/geometry/se3.h"

namespace bivo::odometry::synth {

namespace {

struct Sinusoid {
  double amplitude, omega, phase;  // amplitude * sin(omega t + phase)
};

// One band of random sinusoids per axis, amplitudes ~ 1/f and weighted per axis.
std::vector<std::vector<Sinusoid>> random_band(HashRng& rng, int count, double f_min, double f_max,
                                               const Eigen::Vector3d& weights, double share) {
  std::vector<std::vector<Sinusoid>> axes(3);
  for (int a = 0; a < 3; ++a) {
    for (int k = 0; k < count; ++k) {
      const double f = rng.uniform(f_min, f_max);
      const double omega = 2.0 * M_PI * f;
      // Speed amplitude ~ weight * share; displacement amplitude = speed / omega (~ 1/f).
      axes[a].push_back({weights[a] * share * rng.uniform(0.5, 1.0) / omega, omega, rng.uniform(0.0, 2.0 * M_PI)});
    }
  }
  return axes;
}

Eigen::Vector3d evaluate(const std::vector<std::vector<Sinusoid>>& axes, double t, double scale) {
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  for (int a = 0; a < 3; ++a) {
    for (const Sinusoid& s : axes[a]) x[a] += scale * s.amplitude * std::sin(s.omega * t + s.phase);
  }
  return x;
}

}  // namespace

MotionSpeeds mean_speeds(const io::Trajectory& trajectory) {
  MotionSpeeds s;
  if (trajectory.size() < 2) return s;
  double length = 0, angle = 0;
  for (std::size_t k = 1; k < trajectory.size(); ++k) {
    const Eigen::Isometry3d rel = trajectory[k - 1].T_wc.inverse() * trajectory[k].T_wc;
    length += rel.translation().norm();
    angle += solvers::se3::rotation_angle(rel);
  }
  const double duration = trajectory.back().timestamp - trajectory.front().timestamp;
  if (duration > 0) {
    s.linear_mps = length / duration;
    s.angular_rps = angle / duration;
  }
  return s;
}

io::Trajectory generate_handheld_motion(const HandheldMotionOptions& o) {
  if (!(o.duration_s > 0) || !(o.rate_hz > 0) || !std::isfinite(o.start_time_s)) {
    throw Error("hand-held motion: duration (" + std::to_string(o.duration_s) + " s) and rate (" +
                std::to_string(o.rate_hz) + " Hz) must be positive");
  }
  if (!(o.mean_linear_speed_mps >= 0) || !(o.mean_angular_speed_dps >= 0) || o.sinusoids_per_axis < 1 ||
      !(o.min_frequency_hz > 0) || !(o.max_frequency_hz >= o.min_frequency_hz) ||
      !(o.tremor_share >= 0 && o.tremor_share < 1)) {
    throw Error("hand-held motion: invalid speed, frequency or tremor parameters");
  }
  const double samples = o.duration_s * o.rate_hz;
  if (!(samples < static_cast<double>(io::input_limits().max_list_entries))) {
    std::ostringstream m;
    m << "hand-held motion: " << o.duration_s << " s at " << o.rate_hz << " Hz is more than "
      << io::input_limits().max_list_entries << " poses (the list limit; raise with --max-list-entries)";
    throw Error(m.str());
  }
  HashRng rng(o.seed, 0x68616e64ull);  // "hand"
  const auto trans = random_band(rng, o.sinusoids_per_axis, o.min_frequency_hz, o.max_frequency_hz,
                                 o.translation_axis_weights, 1.0 - o.tremor_share);
  const auto trans_tremor =
      random_band(rng, 2, o.tremor_min_hz, o.tremor_max_hz, o.translation_axis_weights, o.tremor_share);
  const auto rot = random_band(rng, o.sinusoids_per_axis, o.min_frequency_hz, o.max_frequency_hz,
                               o.rotation_axis_weights, 1.0 - o.tremor_share);
  const auto rot_tremor =
      random_band(rng, 2, o.tremor_min_hz, o.tremor_max_hz, o.rotation_axis_weights, o.tremor_share);

  const int n = static_cast<int>(std::floor(o.duration_s * o.rate_hz)) + 1;
  const auto build = [&](double ts, double rs) {
    io::Trajectory out(n);
    for (int k = 0; k < n; ++k) {
      const double t = k / o.rate_hz;
      out[k].timestamp = o.start_time_s + t;
      out[k].T_wc.linear() = solvers::se3::so3_exp(evaluate(rot, t, rs) + evaluate(rot_tremor, t, rs));
      out[k].T_wc.translation() = evaluate(trans, t, ts) + evaluate(trans_tremor, t, ts);
    }
    return out;
  };
  // Translation is linear in its scale; the rotation angle nearly so: a few fixed-point
  // rescalings reach the target mean speeds.
  double ts = 1.0, rs = 1.0;
  const double target_w = o.mean_angular_speed_dps * M_PI / 180.0;
  io::Trajectory out = build(ts, rs);
  for (int it = 0; it < 4; ++it) {
    const MotionSpeeds s = mean_speeds(out);
    if (s.linear_mps > 0) ts *= o.mean_linear_speed_mps / s.linear_mps;
    if (s.angular_rps > 0) rs *= target_w / s.angular_rps;
    out = build(ts, rs);
  }
  return out;
}

io::Trajectory resample_trajectory(const io::Trajectory& motion, double start_offset_s, int frames, double fps,
                                   const std::string& source, double max_gap_s) {
  if (frames < 1) throw Error("need at least 1 frame, got " + std::to_string(frames));
  if (!(fps > 0)) throw Error("frame rate must be positive, got " + std::to_string(fps));
  if (!(start_offset_s >= 0 && std::isfinite(start_offset_s))) {
    throw Error("start offset must be finite and >= 0 s, got " + std::to_string(start_offset_s));
  }
  if (motion.size() < 2) {
    throw Error("trajectory '" + source + "' has " + std::to_string(motion.size()) +
                " pose(s); at least 2 are needed to interpolate frame poses");
  }
  const double t0 = motion.front().timestamp + start_offset_s;
  const double needed_end = t0 + (frames - 1) / fps;
  if (needed_end > motion.back().timestamp + 1e-9) {
    std::ostringstream m;
    m << "trajectory '" << source << "' is too short: " << frames << " frames at " << fps << " Hz from offset "
      << start_offset_s << " s need " << (frames - 1) / fps + start_offset_s << " s, it covers "
      << motion.back().timestamp - motion.front().timestamp << " s (" << motion.size() << " poses)";
    throw Error(m.str());
  }
  io::Trajectory out(frames);
  std::size_t j = 0;
  for (int k = 0; k < frames; ++k) {
    const double t = std::min(t0 + k / fps, motion.back().timestamp);
    while (j + 2 < motion.size() && motion[j + 1].timestamp < t) ++j;
    const io::StampedPose& a = motion[j];
    const io::StampedPose& b = motion[j + 1];
    const double gap = b.timestamp - a.timestamp;
    if (gap > max_gap_s) {
      std::ostringstream m;
      m.precision(17);
      m << "trajectory '" << source << "' has a gap of " << gap << " s between poses at " << a.timestamp << " and "
        << b.timestamp << " (frame " << k << " at t=" << t << "); choose another start offset";
      throw Error(m.str());
    }
    const double s = gap > 0 ? std::clamp((t - a.timestamp) / gap, 0.0, 1.0) : 0.0;
    const Eigen::Quaterniond qa(a.T_wc.linear()), qb(b.T_wc.linear());
    out[k].timestamp = t0 + k / fps;
    out[k].T_wc.linear() = qa.slerp(s, qb).normalized().toRotationMatrix();
    out[k].T_wc.translation() = (1 - s) * a.T_wc.translation() + s * b.T_wc.translation();
  }
  return out;
}

io::Trajectory retime_trajectory(const io::Trajectory& motion, double scale) {
  if (!(scale > 0 && scale <= 100))
    throw Error("trajectory time scale must be in (0, 100], got " + std::to_string(scale));
  io::Trajectory out = motion;
  if (scale == 1.0 || out.empty()) return out;
  const double t0 = motion.front().timestamp;
  for (io::StampedPose& p : out) p.timestamp = t0 + (p.timestamp - t0) / scale;
  return out;
}

Eigen::Isometry3d anchor_transform(const Eigen::Isometry3d& reference_T_wc, const Eigen::Isometry3d& nominal_T_wc) {
  return nominal_T_wc * reference_T_wc.inverse();
}

}  // namespace bivo::odometry::synth
