#pragma once
// Whole-problem backend "ipopt-nlp": Ipopt (interior point, MUMPS) on the NONLINEAR
// epsilon-constraint problem (eq. `bounded objective form`)
//   min F_1(x)  s.t.  F_2(x) <= epsilon
// over the problem's manifold, not on one linearized step.
//
// Variables: tangent coordinates d around a centre x_c, x(d) = x_c (+) d. The Jacobian of
// r_j(x(d)) in d is J_j(x(d)) T(d), with J_j the problem's tangent Jacobian at x(d) (left
// perturbation at x(d)) and T(d) = d [(x_c (+) (d + e)) (-) x(d)] / d e at e = 0, the map from a
// change of d to the perturbation at x(d): T = I exactly on a Euclidean manifold; on others (SE(3))
// T(d) is the central difference of minus(retract(x_c, d +- h e_k), x(d)), and T(0) = I
// exactly. Ipopt is run in PASSES that re-centre x_c at the last solution (so the final
// pass sits at d ~ 0, where T is exact) and re-linearize (robust problems re-estimate their
// weights, an epsilon policy sees the new linearization), until a pass moves x by less than
// Ipopt's own precision (see ipopt_nlp_backend.cpp).
//
// Hessian: Gauss-Newton, sigma 2 T^T J_1^T W_1 J_1 T + lambda 2 T^T J_2^T W_2 J_2 T (exact for
// problems linear in d; Ipopt still converges to a KKT point of the nonlinear problem since
// gradients are exact). Functions are scaled: f = F_1 / F_1(x_c), g = F_2 / epsilon - 1 <= 0;
// bound_relax_factor = 0, tol 1e-10 (scaled), constr_viol_tol 1e-10 epsilon.
//
// Summary: multiplier = mu of F_1 + mu F_2 (from Ipopt's constraint multiplier), epsilon,
// feasible = F_2 <= epsilon (1 + 1e-6). epsilon below min F_2 (Ipopt reports an infeasible
// problem) -> termination kBackendFailure, feasible = false, multiplier +inf, message
// "epsilon infeasible: ...", x = Ipopt's point of least violation when it is finite and lowers
// F_2, else the start. Never NaN in x.
#include <memory>

#include "solvers/whole_problem_backend.h"

namespace bivo::solvers {

std::unique_ptr<WholeProblemBackend> make_ipopt_nlp_backend();

}  // namespace bivo::solvers
