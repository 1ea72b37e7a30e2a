// Sweeps the epsilon-constraint Pareto front of an analytic bi-objective least-squares
// problem with the exact QCQP step and prints it with its knee; built against the installed
// package (find_package(bivo), target bivo::problems).
#include <cstdio>

#include "problems/linear_least_squares_pair.h"
#include "solvers/pareto.h"

int main() {
  auto problem = bivo::problems::LinearLeastSquaresPair::well_conditioned(4, 1);
  bivo::solvers::ParetoOptions options;
  options.points = 7;
  const auto front = bivo::solvers::sweep_epsilon(problem, Eigen::VectorXd::Zero(4), options);
  for (const auto& p : front.points) std::printf("F1 %.6f  F2 %.6f  mu %.4f\n", p.f1, p.f2, p.multiplier);
  const auto knee = bivo::solvers::knee_index(front.points);
  std::printf("knee %d of %zu points\n", knee ? static_cast<int>(*knee) : -1, front.points.size());
  return front.points.size() == 7 ? 0 : 1;
}
