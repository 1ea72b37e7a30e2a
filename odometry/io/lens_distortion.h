#pragma once
// Radial-tangential lens distortion (Brown-Conrady, OpenCV's order k1 k2 p1 p2 k3), the TUM
// presets chosen by sequence name, and the undistortion of a loaded RGB-D frame.
//
// TUM's freiburg1 and freiburg2 images are published as the Kinect took them, distorted
// (freiburg3 ones are already undistorted). The residuals of odometry/ assume a pinhole
// camera: a reference pixel is back-projected with K^-1 and a warped point projected with K.
// Near the corners of a freiburg1 image the pinhole model is off by up to ~6 % of the
// radius (tens of pixels), which bends the 3-D points the depth objective compares and the
// image motion under rotation. Undistorting both images once, at loading, makes every
// method's model hold; the warp itself stays pinhole.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "odometry/io/camera_intrinsics.h"

namespace bivo::odometry::io {

struct Distortion {
  double k1 = 0.0, k2 = 0.0, p1 = 0.0, p2 = 0.0, k3 = 0.0;

  bool is_identity() const { return k1 == 0.0 && k2 == 0.0 && p1 == 0.0 && p2 == 0.0 && k3 == 0.0; }
  // The distorted normalized image point of the ideal (pinhole) one (x, y) = K^-1 [u v 1]:
  //   r^2 = x^2 + y^2,  g = 1 + k1 r^2 + k2 r^4 + k3 r^6,
  //   x_d = g x + 2 p1 x y + p2 (r^2 + 2 x^2),  y_d = g y + p1 (r^2 + 2 y^2) + 2 p2 x y.
  std::array<double, 2> distort(double x, double y) const;
};

// TUM calibration page values by sequence name: freiburg1 / freiburg2 (also "fr1" / "fr2")
// have distortion, everything else (freiburg3, the synthetic renderings) none.
Distortion distortion_for_sequence(const std::string& name_or_path);

// "k1 k2 p1 p2 k3" or "none" (the --distortion override); throws bivo::Error naming the text
// on anything else.
Distortion parse_distortion(const std::string& text);

struct RgbdImage;

// The resampling of one camera's frames to the pinhole model, computed once per sequence:
// every output pixel (u, v) takes the input at K distort(K^-1 [u v 1]). Intensity is
// interpolated bilinearly (positions outside the input are clamped to its border, so the
// border has no artificial edge); depth takes the nearest input pixel (interpolating across a
// depth edge would invent surfaces) and is missing (0) where the position falls outside.
class Undistortion {
 public:
  Undistortion(const Intrinsics& K, const Distortion& d, int width, int height);

  bool is_identity() const { return identity_; }
  // Undistorts `image` in place; throws bivo::Error when its size is not the map's. The
  // output is written into buffers kept from the previous call (which then receive the
  // input's), so a stream of frames causes no fresh page faults: one map per thread.
  void apply(RgbdImage& image) const;
  // Where output pixel (u, v) reads the input (for tests): in pixels of the input.
  std::array<double, 2> source(int u, int v) const;

 private:
  Intrinsics K_;
  Distortion d_;
  int width_, height_;
  bool identity_;
  // Per output pixel: the top-left input pixel of the bilinear cell and the fractions.
  std::vector<std::int32_t> cell_;
  std::vector<float> fu_, fv_;
  std::vector<std::int32_t> nearest_;                         // -1: outside the input (depth missing)
  mutable std::vector<float> spare_intensity_, spare_depth_;  // see apply()
};

}  // namespace bivo::odometry::io
