#pragma once
// Per-image statistics that drive the lambda / epsilon policies (paper Sec. III-A):
// the complexity metric pi of eqs. `image complexity metric` / `depth complexity metric`,
// variances for the scale factor of eq. `scale factor`, and medians for Tykkala's lambda.
#include <limits>

#include "odometry/rgbd_pyramid.h"

namespace bivo::odometry {

// pi(I) = 1/((v-2)(h-2)) sum_{interior} |I(i+1,j)-I(i-1,j)| + |I(i,j+1)-I(i,j-1)|.
// Computed as mean |row difference| + mean |column difference|, which is the same number.
// With skip_missing (depth) a difference is used only when both of its values are valid
// (> 0) and each mean runs over the differences used, so a fully valid image gives exactly
// the paper's value and holes do not bias it. A direction without usable differences adds 0.
double complexity_metric(const ImageF& image, bool skip_missing, int threads = 1);

// Population variance of the values (valid ones only with skip_missing); 0 if none.
double variance(const ImageF& image, bool skip_missing, int threads = 1);

// Median of the values (valid ones only with skip_missing); 0 if none. Exact (the mean of the
// two middle values for an even count).
double median(const ImageF& image, bool skip_missing);

// false when every value lies within `range` of the first (a black, saturated or constant
// image); stops at the first value that does not (the first few pixels of any real image).
bool has_contrast(const ImageF& image, float range = 1.0f);

// Everything the policies need from one frame, computed once per frame. Sums are taken over
// fixed row chunks (threads change the time, not the numbers). The exact medians cost about
// as much as all the sums together (two histogram passes and a selection per image) and only
// Tykkala's lambda reads them (reads_medians() in odometry_methods.h): they are left out
// unless asked for, NaN with has_medians = false, and add_medians() fills them in on demand.
struct FrameStatistics {
  double pi_intensity = 0.0;  // gray levels per pixel
  double pi_depth = 0.0;      // metres per pixel
  double var_intensity = 0.0, var_depth = 0.0;
  bool has_medians = false;
  double median_intensity = std::numeric_limits<double>::quiet_NaN();
  double median_depth = std::numeric_limits<double>::quiet_NaN();
  double valid_depth_fraction = 0.0;
};
FrameStatistics frame_statistics(const RgbdLevel& level, int threads = 1, bool with_medians = false);
// median(I) and median(D > 0) of the level into s (a no-op when s has them).
void add_medians(FrameStatistics& s, const RgbdLevel& level);

}  // namespace bivo::odometry
