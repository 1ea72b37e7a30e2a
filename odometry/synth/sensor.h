#pragma once
// Sensor models of the synthetic RGB-D camera (a Kinect-like structured-light sensor as in
// TUM freiburg3). Every parameter is documented in docs/synthetic.md.
#include <cstdint>

namespace bivo::odometry::synth {

// Pinhole camera; defaults are TUM freiburg3 (already undistorted), 640x480.
// Pixel (u, v) has its centre at integer coordinates, as in the TUM tools and OpenCV.
struct PinholeCamera {
  int width = 640, height = 480;
  double fx = 535.4, fy = 539.2, cx = 320.1, cy = 247.6;
};

struct DepthSensorModel {
  // Axial noise sigma_z = noise_coeff * z^2 [m] (Khoshelham & Elberink 2012, Kinect).
  double noise_coeff = 1.425e-3;
  // The noise is spatially correlated (the sensor matches its pattern over a window):
  // Gaussian correlation of this standard deviation in pixels, 0 = independent pixels.
  // Fitted to real fr3 depth frames (docs/synthetic.md, "Sensor model").
  double noise_correlation_px = 2.0;
  // Structured light measures disparity d = f_ir * baseline / z in the infrared camera (focal
  // length ir_focal_px, not the colour camera's) in steps of disparity_step_px (Kinect: 1/8
  // pixel), so depth is quantized in steps of z^2 * step / (f_ir * baseline): 2.93e-3 z^2,
  // as measured between the depth levels of real fr3 frames (docs/synthetic.md).
  double baseline_m = 0.075;
  double ir_focal_px = 569.4;
  double disparity_step_px = 0.125;
  // No measurement outside [min_range, max_range] (depth along the optical axis).
  double min_range_m = 0.5, max_range_m = 4.0;
  // No measurement where the angle between viewing ray and surface normal exceeds this.
  double max_incidence_deg = 75.0;
  // Occluding edges: a pixel whose true depth differs from a 4-neighbour's by more than
  // occlusion_jump_rel * (the nearer depth), or whose neighbour sees nothing, is missing,
  // together with the pixels within occlusion_band_px (Chebyshev distance) of it.
  double occlusion_jump_rel = 0.05;
  int occlusion_band_px = 2;
};

struct IntensitySensorModel {
  // Per-channel Gaussian noise of variance read_noise^2 + shot_noise_gain * I (I in gray
  // levels 0..255), then rounding to 8 bits with saturation.
  double read_noise = 1.0;
  double shot_noise_gain = 0.03;
  // Exposure: every frame's radiance is multiplied by exp(exposure_jitter * N(0,1)),
  // independently per frame (0 = constant exposure, the default).
  double exposure_jitter = 0.0;
  // Radiance of albedo 1 under full light, in gray levels.
  double full_scale = 255.0;
};

}  // namespace bivo::odometry::synth
