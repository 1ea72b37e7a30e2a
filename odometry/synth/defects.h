#pragma once
// Real sensor defects of a Kinect-class RGB-D camera, each switchable (all off by default, so
// a rendering without them is byte-identical to one made before they existed) and each a
// pure function of (seed, frame, pixel). Sources and values: docs/synthetic.md, "Sensor
// defects".
//
// Depth: a static smooth bias field (radial + low-frequency, in disparity units, so the
// relative depth error grows with z as Herrera et al. 2012 model it); the depth camera
// offset from the colour camera (misregistration); its own capture time (unsynchronized).
// Colour: rolling shutter, motion blur (poses sampled within the exposure), auto-exposure
// gain drifting from frame to frame, vignetting.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "odometry/io/vignetting.h"

namespace bivo::odometry::synth {

struct SensorDefects {
  // Depth bias: the measured disparity is off by delta_d(u, v) [px] at every pixel (a fixed
  // pattern of the sensor), so depth is multiplied by 1 / (1 - z delta_d / (f_ir b)):
  // relative error ~ z delta_d / (f_ir b), growing linearly with depth. delta_d = radial
  // term + low-frequency term, each given as the relative depth error it causes at 1 m.
  double bias_radial = 0.0;           // relative error at 1 m at the image corner (rho = 1), 0 at the centre
  double bias_lowfreq = 0.0;          // RMS relative error at 1 m of a random smooth field
  double bias_wavelength_px = 400.0;  // its shortest wavelength; the field is static over a sequence
  // Fixed-pattern depth noise: this share of the depth noise variance is the same in every
  // frame (a pattern in image coordinates, as the Kinect's speckle matching errors are), the
  // rest independent per frame. 0 = all independent (the sensor model's default).
  double static_noise_share = 0.0;
  // Depth noise sigma_z = noise_coeff * z^noise_exponent (z in m): 2 is the Kinect v1's
  // disparity noise of constant spread (Khoshelham & Elberink 2012); a sensor whose speckle
  // contrast fades with distance has a larger exponent, as the real fr3 depth residual shows.
  double noise_exponent = 2.0;
  // Frame-to-frame disparity offset [px], the same at every pixel (a global shift of the
  // matched pattern, e.g. with the projector's temperature): an AR(1) walk o_k = offset_memory o_{k-1} +
  // offset_step N(0,1). Its relative depth error z o_k / (f_ir b) grows with depth.
  double disparity_offset_step_px = 0.0;
  double disparity_offset_memory = 0.0;
  // Speckle matching failures: this share of the measured pixels, independently per frame,
  // get a disparity off by 2-8 px (either sign): the stored depth is far from the surface.
  double speckle_outliers = 0.0;
  // Flying pixels: this share of the pixels the occlusion band would drop is kept, at a depth
  // between the pixel's own surface and the farthest-differing one within the band
  // (mixed returns at depth edges, Nguyen, Izadi, Lovell 2012).
  double flying_pixels = 0.0;
  // Misregistration: depth is measured by a camera at T_colour_depth (translation [m], then a
  // rotation vector [rad]) but stored as if taken by the colour camera.
  Eigen::Vector3d depth_offset_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d depth_rotation_rad = Eigen::Vector3d::Zero();
  // Unsynchronized: frame k's depth is taken at t_k + delay_k (its own timestamp in depth.txt),
  // colour at t_k. delay_k drifts as a random walk of steps N(0, depth_delay_step_s^2)
  // reflected into [depth_delay_min_s, depth_delay_max_s], started uniformly in it (TUM
  // fr1/rpy: 0-13 ms, drifting by ~1-2 ms per frame).
  double depth_delay_min_s = 0.0, depth_delay_max_s = 0.0;
  double depth_delay_step_s = 0.0015;
  // Rolling shutter: rows are read top to bottom over readout_s; the frame's timestamp is the
  // middle row's. Motion blur: each row integrates over exposure_s, sampled at
  // blur_samples poses (box filter). 0 = global shutter / instantaneous.
  double readout_s = 0.0;
  double exposure_s = 0.0;
  int blur_samples = 5;
  // Auto-exposure: log gain is an AR(1) walk, log g_k = gain_memory log g_{k-1} + gain_step N(0,1).
  double gain_step = 0.0;
  double gain_memory = 0.9;
  // Vignetting: radiance times 1 - vignetting * rho^2, rho = distance to the principal point
  // over the distance of the farthest image corner.
  double vignetting = 0.0;

  bool depth_bias() const { return bias_radial != 0.0 || bias_lowfreq != 0.0; }
  bool misregistered() const { return !depth_offset_m.isZero(0) || !depth_rotation_rad.isZero(0); }
  bool unsynchronized() const { return depth_delay_min_s != 0.0 || depth_delay_max_s != 0.0; }
  bool timed_colour() const { return readout_s > 0.0 || exposure_s > 0.0; }
  bool depth_outliers() const { return speckle_outliers > 0.0 || flying_pixels > 0.0; }
  bool any() const {
    return depth_bias() || static_noise_share > 0.0 || misregistered() || unsynchronized() || timed_colour() ||
           gain_step > 0.0 || vignetting > 0.0 || noise_exponent != 2.0 || disparity_offset_step_px > 0.0 ||
           depth_outliers();
  }
};

// Throws bivo::Error naming the field when a defect parameter is out of range.
void validate(const SensorDefects& defects);

// The defect classes a rendering can be made without (`bivo synth --stress-profile P
// --without NAME,...`), each the fields of one defect above: rolling-shutter, blur,
// vignetting, gain, depth-bias, misregistration, depth-delay, outliers, disparity-offset.
const std::vector<std::string>& defect_class_names();
// The same names, comma-separated, for messages.
const std::string& defect_class_list();

// Switches defect class `name` off in `defects` (throws bivo::Error naming the classes on an
// unknown name); every other field is kept.
void switch_off(SensorDefects& defects, const std::string& name);

// The disparity bias delta_d(u, v) [px] of a width x height image (row-major), for the
// sensor's f_ir * b [px m]: zero everywhere when no bias is switched on. Static: depends on
// the seed, not on the frame.
std::vector<float> disparity_bias_field(const SensorDefects& defects, std::uint64_t seed, int width, int height,
                                        double cx, double cy, double ir_focal_baseline);

// The depth measured for true depth z under disparity bias delta_d: z / (1 - z delta_d / fb).
inline double biased_depth(double z, double delta_d, double ir_focal_baseline) {
  return z / (1.0 - z * delta_d / ir_focal_baseline);
}

// rho^2 of pixel (u, v), as the tracker divides a stated fall-off out (io/vignetting.h).
using io::normalized_radius2;

// Exposure gain of frame k (1 when gain_step == 0).
double auto_exposure_gain(const SensorDefects& defects, std::uint64_t seed, std::uint64_t frame);

// Disparity offset of frame k [px] (0 when disparity_offset_step_px == 0).
double disparity_offset(const SensorDefects& defects, std::uint64_t seed, std::uint64_t frame);

// The disparity error [px] of a speckle matching failure at pixel i of frame k, or 0 when
// the pixel matched (probability 1 - speckle_outliers).
double speckle_disparity_error(const SensorDefects& defects, std::uint64_t seed, std::uint64_t frame,
                               std::uint64_t pixel);

// Whether pixel i of frame k, dropped by the occlusion band, is kept as a flying pixel, and
// at which fraction t in [0, 1) of the way from its own depth to the other side's.
bool flying_pixel(const SensorDefects& defects, std::uint64_t seed, std::uint64_t frame, std::uint64_t pixel,
                  double* t);

// Depth capture delay of frame k after its colour timestamp [s].
double depth_delay(const SensorDefects& defects, std::uint64_t seed, std::uint64_t frame);

// Offsets, relative to the frame timestamp, of the colour samples of row v: blur_samples
// times evenly spread (box filter) over the row's exposure, centred on its read-out time.
std::vector<double> row_sample_times(const SensorDefects& defects, int row, int height);

// T_colour_depth of the misregistration.
Eigen::Isometry3d colour_to_depth(const SensorDefects& defects);

}  // namespace bivo::odometry::synth
