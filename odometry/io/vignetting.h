#pragma once
// A camera-fixed radial fall-off of the colour image's brightness, 1 - k rho^2, rho the
// distance to the principal point over that of the farthest corner: the vignetting model that
// bivo synth renders (odometry/synth/defects.h) and a sequence may state (scene.json,
// sensor_description.h). Dividing it out is a flat-field correction, as a photometrically
// calibrated camera's frames get before tracking.
#include "odometry/io/camera_intrinsics.h"
#include "odometry/io/tum_dataset.h"

namespace bivo::odometry::io {

// rho^2 of pixel (u, v): squared distance to (cx, cy) over that of the farthest corner.
double normalized_radius2(double u, double v, int width, int height, double cx, double cy);

// The image's intensity divided by 1 - k rho^2 (principal point of K, the image's size):
// unchanged for k = 0; bivo::Error for k outside [0, 1).
void divide_out_vignetting(RgbdImage& image, double k, const Intrinsics& K);

}  // namespace bivo::odometry::io
