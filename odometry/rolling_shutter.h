#pragma once
// Rolling shutter: the colour image's rows are read top to bottom over a readout time, row v
// at t + ((v + 0.5) / height - 0.5) readout (the timestamp is the middle row's, as bivo synth
// renders it). A colour image is moved to one instant, its timestamp, by the camera's velocity
// there (TrackerOptions::readout_time).
#include <Eigen/Geometry>

#include "odometry/depth_retiming.h"
#include "odometry/io/camera_intrinsics.h"
#include "odometry/rgbd_pyramid.h"

namespace bivo::odometry {

// Row v's time offset from the image's timestamp [s].
double row_time(int v, int height, double readout);

// `intensity` read by a rolling shutter while the camera moved at `velocity` (log(T_21) per
// second, about the middle row's time), as a global shutter at that time would have seen it. Each
// pixel's point (its depth in `depth`, metres; a missing depth takes the nearest valid one to
// its left in the row, else the image's median) is followed to the row that read it (the
// row's own pose, twice: the row depends on where the point lands) and the intensity there is
// interpolated bilinearly; a point read outside the image keeps its pixel's value.
// The per-pixel pass by the best kernels of this CPU, or by those of `isa` (rgbd_kernels.h:
// bit-identical), its rows split over `threads` threads (the result does not depend on it).
ImageF global_shutter_intensity(const ImageF& intensity, const ImageF& depth, const io::Intrinsics& K,
                                const solvers::se3::Vector6d& velocity, double readout, int threads = 1);
ImageF global_shutter_intensity(const ImageF& intensity, const ImageF& depth, const io::Intrinsics& K,
                                const solvers::se3::Vector6d& velocity, double readout, KernelIsa isa, int threads = 1);

// A copy of `pyramid` whose full-resolution images are moved to its timestamp by the camera's
// velocity there: depth by its delay (retime_depth) when `retime`, colour
// by its rows' times when readout > 0 (with the depth so moved); coarser levels downsampled;
// its depth_delay is 0 once retimed. The colour move's rows are split over `threads` threads.
// At full resolution: retiming at 320x240 kept the fast renderings' worst joint pair above 2 deg.
RgbdPyramid pyramid_at_timestamp(const RgbdPyramid& pyramid, const solvers::se3::Vector6d& velocity, bool retime,
                                 double readout, int threads = 1);

}  // namespace bivo::odometry
