#include "solvers/step/qcqp_socp.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "solvers/conic/dense_kernels.h"
#include "solvers/error.h"

namespace bivo::solvers::conic {

namespace {

void check_data(const ResidualData& f, const char* which, int dim) {
  const auto n = f.r.size();
  if (f.w.size() != n) {
    throw Error(std::string("qcqp socp: ") + which + " has " + std::to_string(n) + " residuals but " +
                std::to_string(f.w.size()) + " weights");
  }
  if (f.J.rows() != n || f.J.cols() != dim) {
    throw Error(std::string("qcqp socp: ") + which + " Jacobian is " + std::to_string(f.J.rows()) + " x " +
                std::to_string(f.J.cols()) + ", expected " + std::to_string(n) + " x " + std::to_string(dim) +
                " (full residuals with Jacobians requested?)");
  }
  // The common case in vectorized passes; the loop names the first bad entry.
  const bool ok =
      kernels::all_finite(n, f.w.data()) && kernels::all_finite(n, f.r.data()) && (n == 0 || f.w.minCoeff() >= 0.0);
  for (Eigen::Index i = 0; i < n && !ok; ++i) {
    if (!(f.w[i] >= 0.0) || !std::isfinite(f.w[i]) || !std::isfinite(f.r[i])) {
      throw Error(std::string("qcqp socp: ") + which + " residual " + std::to_string(i) +
                  " has r = " + std::to_string(f.r[i]) + ", w = " + std::to_string(f.w[i]));
    }
  }
  if (!kernels::all_finite(f.J.size(), f.J.data())) {
    throw Error(std::string("qcqp socp: ") + which + " Jacobian has non-finite entries");
  }
}

void check_epsilon(double epsilon) {
  if (!(epsilon >= 0.0) || !std::isfinite(epsilon)) {
    throw Error("qcqp socp: epsilon must be finite and >= 0, got " + std::to_string(epsilon));
  }
}

// The step and mu from an IPM solution of either form. e1 = residual of objective 1 in the
// cone, radius = the second cone's head (sqrt(eps) or sqrt(eps - floor2)).
QcqpConeStep read_solution(const IpmResult& r, int dim, int cone2_head, double e1_norm_at_d, double radius,
                           const QuadraticModel& m2) {
  if (r.status == IpmStatus::kPrimalInfeasible) {
    QcqpConeStep s = infeasible_step(m2);
    s.iterations = r.iterations;
    s.ipm_status = r.status;
    s.timings = r.timings;
    s.status = "infeasible: IPM certificate";
    return s;
  }
  QcqpConeStep s;
  s.delta = r.x.tail(dim);
  s.iterations = r.iterations;
  s.ipm_status = r.status;
  s.reduced_accuracy = r.reduced_accuracy;
  s.polished = r.polished;
  s.timings = r.timings;
  s.mu = radius > 0.0 ? std::max(0.0, r.z[cone2_head]) * e1_norm_at_d / radius : 0.0;
  s.status = status_text(r) + (r.polished ? " (polished)" : "");
  return s;
}

}  // namespace

IpmSettings step_ipm_settings() {
  IpmSettings s;
  s.feastol = 1e-8;
  s.abstol = 0.0;
  s.reltol = 1e-11;
  s.time_phases = true;  // for `bivo profile` (the step's size dwarfs the clock reads)
  return s;
}

IpmSettings unpolished_step_ipm_settings() {
  IpmSettings s = step_ipm_settings();
  s.polish = false;
  return s;
}

ConeFactor factor_from_model(const QuadraticModel& model) {
  const auto d = model.b.size();
  if (model.H.rows() != d || model.H.cols() != d) {
    throw Error("qcqp socp: model H is " + std::to_string(model.H.rows()) + " x " + std::to_string(model.H.cols()) +
                " but b has " + std::to_string(d) + " entries");
  }
  if (!model.H.allFinite() || !model.b.allFinite() || !std::isfinite(model.a)) {
    throw Error("qcqp socp: quadratic model has non-finite entries");
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (model.H + model.H.transpose()));
  const Eigen::VectorXd lam = es.eigenvalues();
  const double tol = 1e-13 * std::max(lam.maxCoeff(), 0.0);
  const Eigen::VectorXd vb = es.eigenvectors().transpose() * model.b;
  ConeFactor f;
  f.R = Eigen::MatrixXd::Zero(d, d);
  f.c = Eigen::VectorXd::Zero(d);
  for (Eigen::Index i = 0; i < d; ++i) {
    if (lam[i] > tol && lam[i] > 0.0) {
      const double s = std::sqrt(lam[i]);
      f.R.row(i) = s * es.eigenvectors().col(i).transpose();
      f.c[i] = vb[i] / s;
    }
  }
  f.floor = std::max(0.0, model.a - f.c.squaredNorm());
  return f;
}

ConeFactor factor_from_residuals(const ResidualData& data) {
  const int dim = static_cast<int>(data.J.cols());
  check_data(data, "objective", dim);
  const Eigen::Index n = data.r.size();
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(std::max<Eigen::Index>(n, dim + 1), dim + 1);
  const Eigen::VectorXd sw = data.w.cwiseSqrt();
  M.topLeftCorner(n, dim) = sw.asDiagonal() * data.J;
  M.block(0, dim, n, 1) = sw.cwiseProduct(data.r);
  Eigen::HouseholderQR<Eigen::MatrixXd> qr(M);
  const Eigen::MatrixXd R = qr.matrixQR().topRows(dim + 1).triangularView<Eigen::Upper>();
  ConeFactor f;
  f.R = R.topLeftCorner(dim, dim);
  f.c = R.block(0, dim, dim, 1);
  f.floor = R(dim, dim) * R(dim, dim);
  return f;
}

ConicProblem full_qcqp_socp(const ResidualData& f1, const ResidualData& f2, double epsilon) {
  ConicProblem p;
  full_qcqp_socp(f1, f2, epsilon, p);
  return p;
}

void full_qcqp_socp(const ResidualData& f1, const ResidualData& f2, double epsilon, ConicProblem& p) {
  const int dim = static_cast<int>(f1.J.cols());
  check_data(f1, "objective 1", dim);
  check_data(f2, "objective 2", dim);
  check_epsilon(epsilon);
  const int n1 = static_cast<int>(f1.r.size()), n2 = static_cast<int>(f2.r.size());
  const int rows = n1 + n2 + 2;
  p.c.setZero(dim + 1);
  p.c[0] = 1.0;
  p.A.resize(0, dim + 1);
  p.b.resize(0);
  p.cones.nonnegative = 0;
  p.cones.soc = {n1 + 1, n2 + 1};
  p.G.resize(0, 0);
  // G = [-1 0; 0 -W1^{1/2} J1; 0 0; 0 -W2^{1/2} J2] is 7 mostly full columns: written
  // dense, straight into the layout the IPM multiplies with (in a workspace, into the last
  // step's buffers). Each block's column 1 holds W^{1/2} until it is the last one written.
  p.dense_G.resize(rows, dim + 1);
  p.dense_G.col(0).setZero();
  p.dense_G(0, 0) = -1.0;
  p.h.resize(rows);
  p.h[0] = 0.0;
  p.h[n1 + 1] = std::sqrt(epsilon);
  auto block = [&](const ResidualData& f, int row0, int n) {
    auto sw = p.dense_G.col(1).segment(row0, n);
    sw = f.w.cwiseSqrt();
    p.h.segment(row0, n) = sw.cwiseProduct(f.r);
    for (int j = dim - 1; j >= 0; --j) p.dense_G.col(j + 1).segment(row0, n) = -sw.cwiseProduct(f.J.col(j));
  };
  block(f1, 1, n1);
  block(f2, n1 + 2, n2);
  p.dense_G.row(0).tail(dim).setZero();
  p.dense_G.row(n1 + 1).tail(dim).setZero();
}

ConicProblem compressed_qcqp_socp(const ConeFactor& f1, const ConeFactor& f2, double epsilon) {
  check_epsilon(epsilon);
  const int dim = static_cast<int>(f1.c.size());
  if (f2.c.size() != dim || f1.R.rows() != dim || f2.R.rows() != dim) {
    throw Error("qcqp socp: cone factors of different sizes");
  }
  ConicProblem p;
  p.c = Eigen::VectorXd::Zero(dim + 1);
  p.c[0] = 1.0;
  p.A.resize(0, dim + 1);
  p.b.resize(0);
  p.cones.soc = {dim + 1, dim + 1};
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(2 * dim + 2, dim + 1);
  G(0, 0) = -1.0;
  G.block(1, 1, dim, dim) = -f1.R;
  G.block(dim + 2, 1, dim, dim) = -f2.R;
  p.G = G.sparseView();
  p.h.resize(2 * dim + 2);
  p.h << 0.0, f1.c, std::sqrt(std::max(0.0, epsilon - f2.floor)), f2.c;
  return p;
}

QcqpConeStep solve_qcqp_full(const ResidualData& f1, const ResidualData& f2, const QuadraticModel& m2, double epsilon,
                             const IpmSettings& settings) {
  FullFormWorkspace workspace;
  return solve_qcqp_full(f1, f2, m2, epsilon, settings, workspace);
}

QcqpConeStep solve_qcqp_full(const ResidualData& f1, const ResidualData& f2, const QuadraticModel& m2, double epsilon,
                             const IpmSettings& settings, FullFormWorkspace& workspace) {
  check_epsilon(epsilon);
  const int dim = static_cast<int>(f1.J.cols());
  if (epsilon <= factor_from_model(m2).floor) return infeasible_step(m2);
  full_qcqp_socp(f1, f2, epsilon, workspace.socp);
  const IpmResult& r = solve_conic(workspace.socp, settings, workspace.ipm);
  // ||W1^{1/2}(J1 d + r1)|| row by row (no O(n) temporaries).
  const Eigen::VectorXd d = r.x.tail(dim);
  double e1 = 0.0;
  for (Eigen::Index i = 0; i < f1.r.size(); ++i) {
    const double ri = f1.J.row(i).dot(d) + f1.r[i];
    e1 += f1.w[i] * ri * ri;
  }
  return read_solution(r, dim, static_cast<int>(f1.r.size()) + 1, std::sqrt(e1), std::sqrt(epsilon), m2);
}

QcqpConeStep solve_qcqp_compressed(const ConeFactor& f1, const ConeFactor& f2, const QuadraticModel& m2, double epsilon,
                                   const IpmSettings& settings) {
  check_epsilon(epsilon);
  const int dim = static_cast<int>(f1.c.size());
  if (epsilon <= f2.floor) return infeasible_step(m2);
  const ConicProblem p = compressed_qcqp_socp(f1, f2, epsilon);
  const IpmResult r = solve_conic(p, settings);
  const Eigen::VectorXd d = r.x.tail(dim);
  const double e1 = (f1.R * d + f1.c).norm();
  return read_solution(r, dim, dim + 1, e1, std::sqrt(epsilon - f2.floor), m2);
}

QcqpConeStep with_compressed_fallback(QcqpConeStep full, const QuadraticModel& m1, const QuadraticModel& m2,
                                      double epsilon, const IpmSettings& settings) {
  if (!settings.polish || !full.feasible || (full.polished && full.clean())) return full;
  QcqpConeStep c = solve_qcqp_compressed(factor_from_model(m1), factor_from_model(m2), m2, epsilon, settings);
  const std::string note = "full form " + full.status + "; compressed-form fallback " + c.status;
  full.timings += c.timings;
  if (c.feasible && c.clean()) {
    c.iterations += full.iterations;
    c.timings = full.timings;
    c.fallback = true;
    full = c;
  }
  full.status = note;
  return full;
}

QcqpConeStep infeasible_step(const QuadraticModel& m2) {
  // epsilon below min m2: the closest we can get is m2's (minimum-norm) minimizer.
  const ConeFactor f = factor_from_model(m2);
  QcqpConeStep s;
  s.delta = -f.R.completeOrthogonalDecomposition().solve(f.c);
  s.mu = std::numeric_limits<double>::infinity();
  s.feasible = false;
  s.status = "infeasible: epsilon <= min m2";
  return s;
}

StepResult to_step_result(const QcqpConeStep& s) {
  StepResult r;
  r.delta = s.delta;
  r.multiplier = s.mu;
  r.feasible = s.feasible;
  r.iterations = s.iterations;
  r.status = s.status;
  return r;
}

}  // namespace bivo::solvers::conic
