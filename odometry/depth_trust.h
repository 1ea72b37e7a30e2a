#pragma once
// Whether a pair's depth objective can be trusted, decided from the pair's own data (never
// from ground truth): the distance, in the photometric information metric, between a
// bi-objective estimate x and the photometric estimate one Gauss-Newton step of F_I away,
//   T = (x_I - x)^T H_I (x_I - x) / sigma_I^2 = b_I^T H_I^-1 b_I / sigma_I^2,
// with H_I = J_I^T W_I J_I, b_I = J_I^T W_I r_I the model of F_I at x (a score test of "x is
// where the photometric data put the camera"). When the depth objective only moves x within
// the photometric noise, T is chi-square-like with at most 6 degrees of freedom (the
// Hausman variance H_I^-1 - (H_I + lambda H_D)^-1 is smaller than H_I^-1); a biased or
// misregistered depth image moves x by a multiple of that noise and T grows with the pixel
// count. Real image noise is spatially correlated, so the threshold is not the chi-square
// quantile but a parameter chosen by leave-one-sequence-out (docs/odometry.md, "robust").
#include <Eigen/Core>

#include "solvers/problem.h"

namespace bivo::odometry {

struct DepthTrust {
  double statistic = 0.0;            // T above (0 when F_I has no information)
  Eigen::Matrix<double, 6, 1> step;  // x_I - x in the tangent space (Gauss-Newton step of F_I)
  int rank = 0;                      // directions of H_I with information
};

// T from the quadratic model of F_I at x and the intensity noise scale sigma_I of that
// model's weights. Directions in which H_I has no information (eigenvalue below 1e-9 of
// the largest: a textureless image) contribute nothing: there the photometric data cannot
// contradict the depth. Throws bivo::Error on a model that is not 6x6 or not finite.
DepthTrust photometric_distance(const solvers::QuadraticModel& intensity, double sigma_intensity);

}  // namespace bivo::odometry
