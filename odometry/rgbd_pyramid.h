#pragma once
// Image pyramids of one RGB-D frame: level 0 is the full image, each next level halves
// both sizes by 2x2 averaging. Intensity averages all four pixels; depth averages only the
// valid (non-zero) ones and stays 0 (missing) when none of the four is valid.
#include <vector>

#include "odometry/io/camera_intrinsics.h"
#include "odometry/io/tum_dataset.h"
#include "odometry/kernels/kernels.h"

namespace bivo::odometry {

// Row-major float image.
struct ImageF {
  int width = 0, height = 0;
  std::vector<float> data;

  float at(int x, int y) const { return data[static_cast<std::size_t>(y) * width + x]; }
  float& at(int x, int y) { return data[static_cast<std::size_t>(y) * width + x]; }
};

struct RgbdLevel {
  int level = 0;
  ImageF intensity;  // 0..255
  ImageF depth;      // metres, 0 = missing
  io::Intrinsics K;  // intrinsics of this level
  // [I, D] per pixel, interleaved (what the float kernels read; build_pyramid fills it, a
  // problem on a level without it interleaves its own copy). Pooled (pooled_floats.h): the
  // next frame's pyramid reuses these pages; a level is therefore move-only.
  PooledFloats intensity_depth;
};

// The images of levels 1.. are recycled: a pyramid that dies hands them to a per-thread
// spare list and the next build_pyramid() on that thread takes them back (same sizes: no
// page faults, no zero-fill; ~10 % of a 320x240 pair's CPU time before). Level 0 holds the
// decoded frame's arrays and is freed as usual.
struct RgbdPyramid {
  double timestamp = 0.0;         // of the colour image
  double depth_delay = 0.0;       // depth image's time - timestamp [s] (depth_retiming.h)
  std::vector<RgbdLevel> levels;  // [0] = full resolution

  RgbdPyramid() = default;
  ~RgbdPyramid();
  RgbdPyramid(RgbdPyramid&& o) noexcept = default;
  RgbdPyramid& operator=(RgbdPyramid&& o) noexcept;
  RgbdPyramid(const RgbdPyramid&) = delete;
  RgbdPyramid& operator=(const RgbdPyramid&) = delete;
};

ImageF downsample_intensity(const ImageF& fine);
ImageF downsample_depth(const ImageF& fine);

// A copy of `pyramid` whose full-resolution images are replaced by `intensity` and `depth`
// (same size), the coarser levels downsampled from them (build_pyramid's rule); its levels
// interleave [I, D] on demand (RgbdLevel).
RgbdPyramid pyramid_from_full_resolution(const RgbdPyramid& pyramid, ImageF intensity, ImageF depth);

// Throws bivo::Error when levels < 1 or the coarsest level would be smaller than 8x8. Rows
// are split over `threads` threads (the result does not depend on it). The image's arrays
// become level 0 (pass an rvalue to move them instead of copying). Levels finer than
// finest_level (never solved, e.g. 640x480 when tracking at 320x240) get no
// intensity_depth: a problem on such a level interleaves its own copy.
RgbdPyramid build_pyramid(io::RgbdImage image, const io::Intrinsics& K, int levels, int threads = 1,
                          int finest_level = 0);

// Central-difference gradients (x: columns, y: rows), zero on the border; used for the
// image statistics and for visualisation (the residual Jacobians differentiate the
// bilinear interpolant exactly instead).
void central_gradients(const ImageF& image, ImageF& gx, ImageF& gy);

}  // namespace bivo::odometry
