#include "odometry/depth_trust.h"

#include <cmath>
#include <string>

#include <Eigen/Eigenvalues>

#include "solvers/error.h"

namespace bivo::odometry {

DepthTrust photometric_distance(const solvers::QuadraticModel& intensity, double sigma_intensity) {
  if (intensity.H.rows() != 6 || intensity.H.cols() != 6 || intensity.b.size() != 6) {
    throw Error("depth trust: the photometric model must be 6x6 with a 6-vector gradient, got " +
                std::to_string(intensity.H.rows()) + "x" + std::to_string(intensity.H.cols()));
  }
  if (!intensity.H.allFinite() || !intensity.b.allFinite() || !std::isfinite(sigma_intensity)) {
    throw Error("depth trust: the photometric model or its scale is not finite");
  }
  DepthTrust out;
  out.step.setZero();
  if (!(sigma_intensity > 0.0)) return out;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eig(intensity.H);
  const Eigen::Matrix<double, 6, 1> e = eig.eigenvalues();
  const double floor = 1e-9 * e.maxCoeff();
  if (!(e.maxCoeff() > 0.0)) return out;
  // F_I ~ a + 2 b^T d + d^T H d: the step is -H^-1 b, its length in the H metric b^T H^-1 b.
  const Eigen::Matrix<double, 6, 1> c = eig.eigenvectors().transpose() * intensity.b;
  double t = 0.0;
  Eigen::Matrix<double, 6, 1> y = Eigen::Matrix<double, 6, 1>::Zero();
  for (int k = 0; k < 6; ++k) {
    if (!(e[k] > floor)) continue;
    ++out.rank;
    y[k] = -c[k] / e[k];
    t += c[k] * c[k] / e[k];
  }
  out.step = eig.eigenvectors() * y;
  out.statistic = t / (sigma_intensity * sigma_intensity);
  return out;
}

}  // namespace bivo::odometry
