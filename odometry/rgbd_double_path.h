#pragma once
// The residuals and Jacobians of one objective in double precision, term by term: what
// RgbdOdometryProblem::residuals() returns and linearize() gives as full data (want_full),
// and what tests/test_odometry_problem.cpp checks against finite differences (float
// projection, u ~ 300 with an ulp of 3e-5 px, could not match them to 1e-4). Same formulas
// as the float kernels (rgbd_kernels_impl.h); with kCurrent gradients the Jacobian is the
// exact derivative of the residual inside each pixel cell.
#include <Eigen/Geometry>

#include "odometry/reference_terms.h"
#include "odometry/rgbd_pyramid.h"
#include "solvers/problem.h"

namespace bivo::odometry {

struct DoublePathOptions {
  double occlusion_margin = 0.1;
  GradientSource gradients = GradientSource::kCurrent;
};

// r (0 where invalid), J if asked (0 rows where invalid) and w = weights[k] for objective
// depth ? r_D : r_I at T_21 = T. weights holds reference.count entries.
solvers::ResidualData double_residuals(const ReferenceTerms& reference, const RgbdLevel& current,
                                       const Eigen::Isometry3d& T, bool depth, bool with_jacobian,
                                       const float* weights, const DoublePathOptions& options);

}  // namespace bivo::odometry
