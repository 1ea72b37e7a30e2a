#include "odometry/synth/defects.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "odometry/synth/random.h"
#include "solvers/error.h"
#include "solvers/geometry/se3.h"

namespace bivo::odometry::synth {

namespace {

constexpr std::uint64_t kBiasStream = 0xB1A5;
constexpr std::uint64_t kGainStream = 0x6A1E;
constexpr std::uint64_t kDelayStream = 0xDE1A;
constexpr std::uint64_t kOffsetStream = 0x0FF5;
constexpr std::uint64_t kSpeckleStream = 0x5BEC;
constexpr std::uint64_t kFlyingStream = 0xF1E5;
constexpr double kSpeckleMinPx = 2.0, kSpeckleMaxPx = 8.0;
constexpr int kBiasWaves = 6;  // random plane waves summed into the low-frequency field

void check(double value, double lo, double hi, const char* what) {
  if (!(value >= lo && value <= hi)) {
    std::ostringstream m;
    m << "sensor defects: " << what << " must be in [" << lo << ", " << hi << "], got " << value;
    throw Error(m.str());
  }
}

}  // namespace

void validate(const SensorDefects& d) {
  // Beyond +-20 % at 1 m the bias would flip disparities within the 0.5-10 m range.
  check(d.bias_radial, -0.2, 0.2, "radial depth bias (relative at 1 m)");
  check(d.bias_lowfreq, 0.0, 0.2, "low-frequency depth bias (relative at 1 m)");
  check(d.static_noise_share, 0.0, 1.0, "static share of the depth noise variance");
  check(d.noise_exponent, 0.0, 4.0, "depth noise exponent");
  check(d.disparity_offset_step_px, 0.0, 2.0, "disparity offset step [px]");
  check(d.disparity_offset_memory, 0.0, 1.0, "disparity offset memory");
  check(d.speckle_outliers, 0.0, 0.5, "speckle outlier share");
  check(d.flying_pixels, 0.0, 1.0, "flying pixel share of the occlusion band");
  check(d.bias_wavelength_px, 8.0, 1e5, "bias wavelength [px]");
  for (int i = 0; i < 3; ++i) {
    check(d.depth_offset_m[i], -1.0, 1.0, "depth camera offset [m]");
    check(d.depth_rotation_rad[i], -0.5, 0.5, "depth camera rotation [rad]");
  }
  check(d.depth_delay_min_s, -1.0, 1.0, "depth delay minimum [s]");
  check(d.depth_delay_max_s, d.depth_delay_min_s, 1.0, "depth delay maximum [s] (>= minimum)");
  check(d.depth_delay_step_s, 0.0, 1.0, "depth delay step [s]");
  check(d.readout_s, 0.0, 1.0, "rolling-shutter readout [s]");
  check(d.exposure_s, 0.0, 1.0, "exposure [s]");
  check(d.blur_samples, 1, 64, "motion-blur samples");
  check(d.gain_step, 0.0, 1.0, "auto-exposure gain step (sigma of the log gain)");
  check(d.gain_memory, 0.0, 1.0, "auto-exposure gain memory");
  check(d.vignetting, 0.0, 0.9, "vignetting (fall-off at the corner; the tracker divides it out)");
}

namespace {

// One defect class and the fields that make it.
struct DefectClass {
  const char* name;
  void (*off)(SensorDefects&);
};
constexpr DefectClass kDefectClasses[] = {
    {"rolling-shutter", [](SensorDefects& d) { d.readout_s = 0.0; }},
    {"blur", [](SensorDefects& d) { d.exposure_s = 0.0; }},
    {"vignetting", [](SensorDefects& d) { d.vignetting = 0.0; }},
    {"gain", [](SensorDefects& d) { d.gain_step = 0.0; }},
    {"depth-bias", [](SensorDefects& d) { d.bias_radial = d.bias_lowfreq = 0.0; }},
    {"misregistration",
     [](SensorDefects& d) {
       d.depth_offset_m.setZero();
       d.depth_rotation_rad.setZero();
     }},
    {"depth-delay", [](SensorDefects& d) { d.depth_delay_min_s = d.depth_delay_max_s = 0.0; }},
    {"outliers", [](SensorDefects& d) { d.speckle_outliers = d.flying_pixels = 0.0; }},
    {"disparity-offset", [](SensorDefects& d) { d.disparity_offset_step_px = 0.0; }},
};

}  // namespace

const std::vector<std::string>& defect_class_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const DefectClass& c : kDefectClasses) n.emplace_back(c.name);
    return n;
  }();
  return names;
}

const std::string& defect_class_list() {
  static const std::string list = [] {
    std::string l;
    for (const std::string& n : defect_class_names()) l += (l.empty() ? "" : ", ") + n;
    return l;
  }();
  return list;
}

void switch_off(SensorDefects& d, const std::string& name) {
  for (const DefectClass& c : kDefectClasses) {
    if (name == c.name) {
      c.off(d);
      return;
    }
  }
  throw Error("unknown sensor defect '" + name + "' (one of: " + defect_class_list() + ")");
}

std::vector<float> disparity_bias_field(const SensorDefects& d, std::uint64_t seed, int width, int height, double cx,
                                        double cy, double fb) {
  std::vector<float> field(static_cast<std::size_t>(width) * height, 0.0f);
  if (!d.depth_bias()) return field;
  // Plane waves of random direction, wavelength in [L, 3L] and phase; amplitude sqrt(2/K)
  // each gives unit RMS (in expectation over the phases).
  struct Wave {
    double kx, ky, phase;
  };
  std::vector<Wave> waves;
  HashRng rng(seed, kBiasStream);
  for (int i = 0; i < kBiasWaves; ++i) {
    const double angle = rng.uniform(0.0, M_PI);
    const double k = 2.0 * M_PI / (d.bias_wavelength_px * rng.uniform(1.0, 3.0));
    waves.push_back({k * std::cos(angle), k * std::sin(angle), rng.uniform(0.0, 2.0 * M_PI)});
  }
  const double a = std::sqrt(2.0 / kBiasWaves);
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) {
      double lf = 0.0;
      for (const Wave& w : waves) lf += a * std::cos(w.kx * u + w.ky * v + w.phase);
      const double rel = d.bias_radial * normalized_radius2(u, v, width, height, cx, cy) + d.bias_lowfreq * lf;
      field[static_cast<std::size_t>(v) * width + u] = static_cast<float>(rel * fb);  // rel at z = 1 m
    }
  }
  return field;
}

double auto_exposure_gain(const SensorDefects& d, std::uint64_t seed, std::uint64_t frame) {
  if (!(d.gain_step > 0)) return 1.0;
  // Started at its stationary spread, so frame 0 is not special; O(frame) but a few hundred frames.
  double log_gain =
      d.gain_step / std::sqrt(std::max(1e-12, 1.0 - d.gain_memory * d.gain_memory)) * gaussian(seed, kGainStream, 0);
  for (std::uint64_t k = 1; k <= frame; ++k) {
    log_gain = d.gain_memory * log_gain + d.gain_step * gaussian(seed, kGainStream, k);
  }
  return std::exp(log_gain);
}

double disparity_offset(const SensorDefects& d, std::uint64_t seed, std::uint64_t frame) {
  if (!(d.disparity_offset_step_px > 0)) return 0.0;
  // As the exposure gain: started at its stationary spread, O(frame).
  const double m = d.disparity_offset_memory;
  double o = d.disparity_offset_step_px / std::sqrt(std::max(1e-12, 1.0 - m * m)) * gaussian(seed, kOffsetStream, 0);
  for (std::uint64_t k = 1; k <= frame; ++k) o = m * o + d.disparity_offset_step_px * gaussian(seed, kOffsetStream, k);
  return o;
}

double speckle_disparity_error(const SensorDefects& d, std::uint64_t seed, std::uint64_t frame, std::uint64_t pixel) {
  if (!(d.speckle_outliers > 0)) return 0.0;
  const std::uint64_t key = hash3(seed, kSpeckleStream, frame);
  if (uniform01(hash3(key, pixel, 0)) >= d.speckle_outliers) return 0.0;
  const double size = kSpeckleMinPx + (kSpeckleMaxPx - kSpeckleMinPx) * uniform01(hash3(key, pixel, 1));
  return uniform01(hash3(key, pixel, 2)) < 0.5 ? -size : size;
}

bool flying_pixel(const SensorDefects& d, std::uint64_t seed, std::uint64_t frame, std::uint64_t pixel, double* t) {
  if (!(d.flying_pixels > 0)) return false;
  const std::uint64_t key = hash3(seed, kFlyingStream, frame);
  if (uniform01(hash3(key, pixel, 0)) >= d.flying_pixels) return false;
  *t = uniform01(hash3(key, pixel, 1));
  return true;
}

double depth_delay(const SensorDefects& d, std::uint64_t seed, std::uint64_t frame) {
  if (!d.unsynchronized()) return 0.0;
  const double lo = d.depth_delay_min_s, hi = d.depth_delay_max_s, span = hi - lo;
  double delay = lo + span * uniform01(hash3(seed, kDelayStream, 0));
  if (!(span > 0)) return delay;
  for (std::uint64_t k = 1; k <= frame; ++k) {
    delay += d.depth_delay_step_s * gaussian(seed, kDelayStream, k);
    // Reflect at the ends (a step is far smaller than the span: once or twice at most).
    for (int bounce = 0; bounce < 64 && (delay < lo || delay > hi); ++bounce)
      delay = delay < lo ? 2 * lo - delay : 2 * hi - delay;
    delay = std::clamp(delay, lo, hi);
  }
  return delay;
}

std::vector<double> row_sample_times(const SensorDefects& d, int row, int height) {
  const double t_row = ((row + 0.5) / height - 0.5) * d.readout_s;
  const int n = d.exposure_s > 0 ? d.blur_samples : 1;
  std::vector<double> t(n);
  for (int j = 0; j < n; ++j) t[j] = t_row + d.exposure_s * ((j + 0.5) / n - 0.5);
  return t;
}

Eigen::Isometry3d colour_to_depth(const SensorDefects& d) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = solvers::se3::so3_exp(d.depth_rotation_rad);
  T.translation() = d.depth_offset_m;
  return T;
}

}  // namespace bivo::odometry::synth
