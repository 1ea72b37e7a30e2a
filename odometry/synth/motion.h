#pragma once
// Camera motion for synthetic sequences: a generator of smooth hand-held-like motion, and
// the resampling / re-anchoring of any (real or generated) trajectory to the frame times
// of a rendered sequence.
#include <cstdint>
#include <string>

#include <Eigen/Geometry>

#include "odometry/io/trajectory.h"

namespace bivo::odometry::synth {

// Hand-held motion: in the camera frame of a reference pose, translation and rotation
// vector are each a sum of random sinusoids per axis (frequencies uniform in
// [min_frequency_hz, max_frequency_hz], amplitudes ~ 1/f so slow sway dominates, random
// phases) plus a small tremor band (tremor_frequency_hz range, tremor_share of the speed).
// Amplitudes are then scaled so the mean linear and angular speeds equal the targets.
// Per-axis weights: mostly sideways (x) translation and yaw (about y), like a person
// sweeping a camera along a scene.
struct HandheldMotionOptions {
  std::uint64_t seed = 1;
  double duration_s = 4.0;
  double rate_hz = 100.0;     // sample rate of the produced trajectory (mocap-like)
  double start_time_s = 0.0;  // timestamp of the first pose
  double mean_linear_speed_mps = 0.3;
  double mean_angular_speed_dps = 20.0;
  int sinusoids_per_axis = 4;
  double min_frequency_hz = 0.1, max_frequency_hz = 1.0;
  double tremor_min_hz = 2.0, tremor_max_hz = 6.0, tremor_share = 0.1;
  Eigen::Vector3d translation_axis_weights{1.0, 0.5, 0.35};  // camera x (right), y (down), z (forward)
  Eigen::Vector3d rotation_axis_weights{0.7, 1.0, 0.4};      // pitch (x), yaw (y), roll (z)
};

io::Trajectory generate_handheld_motion(const HandheldMotionOptions& options);

// Mean linear speed [m/s] and angular speed [rad/s] of a trajectory, by finite differences
// of consecutive poses.
struct MotionSpeeds {
  double linear_mps = 0.0, angular_rps = 0.0;
};
MotionSpeeds mean_speeds(const io::Trajectory& trajectory);

// Poses at t_k = motion.front().timestamp + start_offset_s + k / fps, k = 0..frames-1,
// interpolated between the bracketing poses (translation linearly, rotation by slerp).
// Throws bivo::Error naming `source` when the trajectory has fewer than 2 poses, does not
// span the requested time, or has a gap longer than max_gap_s around a frame time.
io::Trajectory resample_trajectory(const io::Trajectory& motion, double start_offset_s, int frames, double fps,
                                   const std::string& source, double max_gap_s = 0.1);

// The trajectory played `scale` times faster: t -> t_first + (t - t_first) / scale (fast
// motion from a real recording). scale 1 returns it unchanged.
io::Trajectory retime_trajectory(const io::Trajectory& motion, double scale);

// The rigid transform A with A * reference_T_wc = nominal_T_wc. Applying A on the left of
// every pose moves the whole trajectory rigidly: relative motion T_21 = T_w2^-1 T_w1 is unchanged.
Eigen::Isometry3d anchor_transform(const Eigen::Isometry3d& reference_T_wc, const Eigen::Isometry3d& nominal_T_wc);

}  // namespace bivo::odometry::synth
