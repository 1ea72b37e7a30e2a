#include "solvers/step/ipopt_qcqp_backend.h"

#include <cmath>
#include <limits>

#include <IpSolveStatistics.hpp>

#include <Eigen/Dense>

#include "solvers/error.h"
#include "solvers/step/qcqp_socp.h"
#include "solvers/step/scaled_qcqp.h"
#include "solvers/whole/ipopt_one_constraint.h"

namespace bivo::solvers {

namespace {

// min f(y) s.t. g(y) <= 0 of the scaled QCQP; Hessian of the Lagrangian
// 2 (sigma H1~/s1 + lambda H2~/s2).
class QcqpTnlp final : public OneConstraintTnlp {
 public:
  explicit QcqpTnlp(const conic::ScaledQcqp& q) : q_(q) {}

 protected:
  int dim() const override { return q_.dim(); }
  bool objective(const Point& y, double& f) override {
    f = q_.f(y);
    return true;
  }
  bool objective_gradient(const Point& y, Eigen::Map<Eigen::VectorXd> grad) override {
    grad = q_.grad_f(y);
    return true;
  }
  bool constraint(const Point& y, double& g) override {
    g = q_.g(y);
    return true;
  }
  bool constraint_gradient(const Point& y, Eigen::Map<Eigen::VectorXd> grad) override {
    grad = q_.grad_g(y);
    return true;
  }
  bool lagrangian_hessian(const Point&, double sigma, double lambda, Eigen::MatrixXd& H) override {
    H = 2.0 * (sigma / q_.s1 * q_.H1 + lambda / q_.s2 * q_.H2);
    return true;
  }

 private:
  const conic::ScaledQcqp& q_;
};

}  // namespace

StepResult IpoptQcqpBackend::solve(const Subproblem& sp) {
  if (sp.kind != ScalarizationKind::kEpsilonConstraint || sp.lin == nullptr) {
    throw Error("ipopt: needs an epsilon-constraint subproblem with a linearization");
  }
  const Linearization& lin = *sp.lin;
  const conic::ScaledQcqp q = conic::scale_qcqp(lin.f1, lin.f2, sp.epsilon);
  if (sp.epsilon <= conic::factor_from_model(lin.f2).floor) {
    return conic::to_step_result(conic::infeasible_step(lin.f2));
  }
  StepResult r;
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = make_ipopt("ipopt", 0, 1e-12, 200);
  auto* raw = new QcqpTnlp(q);
  Ipopt::SmartPtr<Ipopt::TNLP> nlp = raw;
  const Ipopt::ApplicationReturnStatus st = app->OptimizeTNLP(nlp);
  if (raw->x_final.size() != q.dim() || !raw->x_final.allFinite()) {
    throw Error("ipopt: no finite solution (status " + std::to_string(static_cast<int>(st)) + ")");
  }
  r.delta = q.to_delta(raw->x_final);
  r.multiplier = q.to_mu(std::max(0.0, raw->lambda_final));
  Ipopt::SmartPtr<Ipopt::SolveStatistics> stats = app->Statistics();
  r.iterations = Ipopt::IsValid(stats) ? stats->IterationCount() : 0;
  r.status = (st == Ipopt::Solve_Succeeded || st == Ipopt::Solved_To_Acceptable_Level)
                 ? std::string(st == Ipopt::Solve_Succeeded ? "optimal" : "acceptable")
                 : "ipopt status " + std::to_string(static_cast<int>(st));
  return r;
}

}  // namespace bivo::solvers
