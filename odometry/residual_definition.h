#pragma once
// The reference definition of the paper's residual (eq. `new definition of residual`) and
// its Jacobian, in double precision, term by term: what RgbdOdometryProblem::residuals()
// returns and linearize() gives as full data (want_full). The float kernels
// (odometry/kernels/) compute the same formulas and are tested against this; this one is
// tested against finite differences (tests/test_odometry_problem.cpp). With kCurrent
// gradients the Jacobian is the exact derivative of the residual inside each pixel cell.
#include <Eigen/Geometry>

#include "odometry/reference_terms.h"
#include "odometry/rgbd_pyramid.h"
#include "solvers/problem.h"

namespace bivo::odometry {

struct DoublePathOptions {
  double occlusion_margin = 0.1;
  GradientSource gradients = GradientSource::kCurrent;
  int depth_noise_exponent = 0;  // r_D and its Jacobian times (1 / z)^p, z the reference depth
  // r_I = I_2(y) - ((gain + radial (rho_y^2 - rho_x^2)) I_1(x) + offset) (WarpParams)
  double gain = 1.0, offset = 0.0, radial = 0.0;
};

// r (0 where invalid), J if asked (0 rows where invalid) and w = weights[k] for objective
// depth ? r_D : r_I at T_21 = T. weights holds reference.count entries.
solvers::ResidualData double_residuals(const ReferenceTerms& reference, const RgbdLevel& current,
                                       const Eigen::Isometry3d& T, bool depth, bool with_jacobian, const float* weights,
                                       const DoublePathOptions& options);

}  // namespace bivo::odometry
