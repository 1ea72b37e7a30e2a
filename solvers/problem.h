#pragma once
// The bi-objective problem interface: two weighted nonlinear least-squares objectives
//   F_j(x) = r_j(x)^T W_j r_j(x),  W_j = diag(w_j),  j = 1, 2
// on a manifold (paper eqs. `quadratic form`, `depth quadratic`; in odometry F_1 = F_I,
// F_2 = F_D). The problem knows nothing about the solver that uses it.
#include <array>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "solvers/geometry/manifold.h"
#include "solvers/profiling.h"

namespace bivo::solvers {

// Quadratic model of one objective at the linearization point x (eq. `quadratic form
// after linearisation`): F_j(x (+) d) ~= a + 2 b^T d + d^T H d, with
// a = r^T W r, b = J^T W r, H = J^T W J.
struct QuadraticModel {
  double a = 0.0;
  Eigen::VectorXd b;
  Eigen::MatrixXd H;

  double value(const Eigen::VectorXd& d) const { return a + 2.0 * b.dot(d) + d.dot(H * d); }
};

// Full-size data of one objective (what the paper's n x 6 SOCP needs): residuals r,
// tangent-space Jacobian J = d r(x (+) d) / d d at d = 0 (rows = residuals), weights w.
// The row count is fixed for a problem: a term invalid at x has r = 0 and J = 0.
struct ResidualData {
  Eigen::VectorXd r;
  Eigen::MatrixXd J;  // empty when not requested
  Eigen::VectorXd w;
};

// The quadratic model of F = r^T diag(w) r from full data: a = r^T W r, b = J^T W r,
// H = J^T W J (for problems that form J explicitly; odometry accumulates per pixel instead).
QuadraticModel quadratic_model_of(const ResidualData& d);

struct Linearization {
  QuadraticModel f1, f2;
  std::optional<ResidualData> full1, full2;  // present only when asked for
};

struct LinearizeOptions {
  bool want_full = false;           // also fill Linearization::full1/full2
  bool update_weights = true;       // robust problems re-estimate W_j here (IRLS)
  PhaseProfile* profile = nullptr;  // where the problem records "residuals", "weights",
                                    // "normal_equations" time; may be null
};

class BiObjectiveProblem {
 public:
  virtual ~BiObjectiveProblem() = default;

  virtual std::string name() const = 0;
  virtual const Manifold& manifold() const = 0;

  // Both quadratic models at x; optionally the full residuals. Models are accumulated
  // without forcing n x d storage (odometry sums H and b pixel by pixel).
  virtual Linearization linearize(const Eigen::VectorXd& x, const LinearizeOptions& options) = 0;

  // {F_1(x), F_2(x)} with the weights of the latest linearize(), so a step's actual
  // decrease is measured on the same objective its model approximates.
  virtual std::array<double, 2> evaluate(const Eigen::VectorXd& x) = 0;

  // evaluate() for a caller that will not linearize at x next (a solve's last step): the
  // same values, but the problem need not keep what a linearization at x would reuse (the
  // RGB-D problem then sums F without writing its residual buffers).
  virtual std::array<double, 2> evaluate_only(const Eigen::VectorXd& x) { return evaluate(x); }

  // r_j (and J_j if asked) at x, weights as of the latest linearize(); j in {1, 2}.
  // Whole-problem backends (Ceres, Ipopt over the manifold) use this.
  virtual ResidualData residuals(int j, const Eigen::VectorXd& x, bool with_jacobian) = 0;

  // Why x is a point whose objectives cannot be trusted, or nothing when they can. A problem
  // whose terms drop out as x moves (an image warp that leaves the image) can drive F_1 and
  // F_2 to 0 by measuring nothing; it says so here. Every backend's final x is checked
  // (TerminationReason::kDegeneratePoint instead of convergence there, x reset to the start),
  // and Ceres refuses degenerate trial points. Default: every point is valid.
  virtual std::optional<std::string> degenerate(const Eigen::VectorXd& x) {
    (void)x;
    return std::nullopt;
  }
};

// linearize() of a problem that forms r_j and J_j explicitly: both models from
// problem.residuals(j, x, true) by quadratic_model_of, the full data kept when
// options.want_full, the time recorded as "residuals" and "normal_equations".
Linearization linearize_from_residuals(BiObjectiveProblem& problem, const Eigen::VectorXd& x,
                                       const LinearizeOptions& options);

}  // namespace bivo::solvers
