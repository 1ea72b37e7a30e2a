#include "problems/point_alignment_pair.h"

#include <random>

#include "solvers/error.h"
#include "solvers/geometry/se3.h"

namespace bivo::problems {

namespace se3 = solvers::se3;

PointAlignmentPair::PointAlignmentPair(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  se3::Vector6d xa, xb;
  for (int k = 0; k < 6; ++k) {
    xa(k) = 0.3 * g(rng);
    xb(k) = xa(k) + 0.05 * g(rng);
  }
  const Eigen::Isometry3d Ta = se3::exp(xa), Tb = se3::exp(xb);
  for (int j = 0; j < 2; ++j) {
    p_[j].resize(3, 15);
    q_[j].resize(3, 15);
    for (int i = 0; i < 15; ++i) {
      p_[j].col(i) = Eigen::Vector3d(g(rng), g(rng), g(rng) + 3.0);
      q_[j].col(i) =
          (j == 0 ? Ta : Tb) * Eigen::Vector3d(p_[j].col(i)) + 0.01 * Eigen::Vector3d(g(rng), g(rng), g(rng));
    }
  }
}

solvers::ResidualData PointAlignmentPair::residuals(int j, const Eigen::VectorXd& x, bool with_jacobian) {
  if (j != 1 && j != 2) throw Error("point alignment pair: objective index must be 1 or 2, got " + std::to_string(j));
  if (x.size() != 7) throw Error("point alignment pair: x must have 7 entries, got " + std::to_string(x.size()));
  const Eigen::Isometry3d T = se3::from_ambient(x);
  solvers::ResidualData d;
  const auto& P = p_[j - 1];
  d.r.resize(3 * P.cols());
  d.w = Eigen::VectorXd::Ones(3 * P.cols());
  if (with_jacobian) d.J.resize(3 * P.cols(), 6);
  for (int i = 0; i < P.cols(); ++i) {
    const Eigen::Vector3d Tp = T * Eigen::Vector3d(P.col(i));
    d.r.segment<3>(3 * i) = Tp - q_[j - 1].col(i);
    if (with_jacobian) {
      d.J.block<3, 3>(3 * i, 0).setIdentity();
      d.J.block<3, 3>(3 * i, 3) = -se3::hat(Tp);
    }
  }
  return d;
}

solvers::Linearization PointAlignmentPair::linearize(const Eigen::VectorXd& x,
                                                     const solvers::LinearizeOptions& options) {
  return solvers::linearize_from_residuals(*this, x, options);
}

std::array<double, 2> PointAlignmentPair::evaluate(const Eigen::VectorXd& x) {
  return {residuals(1, x, false).r.squaredNorm(), residuals(2, x, false).r.squaredNorm()};
}

}  // namespace bivo::problems
