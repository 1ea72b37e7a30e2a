#pragma once
// Whole-problem backend "ceres": the weighted sum F_1 + lambda F_2 (eq. `new weighted sum
// form`) as ONE nonlinear least-squares problem over the problem's manifold, solved by Ceres'
// trust-region (Levenberg-Marquardt, dense QR). Residuals come from
// BiObjectiveProblem::residuals(); the SE(3)/Euclidean manifold is wrapped as a
// ceres::Manifold whose Plus is our retraction, and the cost returns J_tangent * P^+ (P the
// manifold's PlusJacobian) so that the product Ceres forms is exactly J_tangent.
// Weights W_j are fixed during one Ceres run (those of one linearize()); robust problems are
// handled by passes (IRLS): linearize (re-weight) -> Ceres run, until a pass no longer
// decreases the re-weighted cost by more than the relative-decrease tolerance or moves x by
// less than the step tolerance (one iteration budget shared by all passes).
// All Ceres code lives in ceres_backend.cpp (heavy headers).
#include <memory>

#include "solvers/whole_problem_backend.h"

namespace bivo::solvers {

std::unique_ptr<WholeProblemBackend> make_ceres_backend();

}  // namespace bivo::solvers
