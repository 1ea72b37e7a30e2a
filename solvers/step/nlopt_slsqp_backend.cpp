#include "solvers/step/nlopt_slsqp_backend.h"

#include <cmath>
#include <limits>

#include <nlopt.hpp>

#include <Eigen/Dense>

#include "solvers/error.h"
#include "solvers/step/qcqp_socp.h"
#include "solvers/step/scaled_qcqp.h"

namespace bivo::solvers {

namespace {

struct Counted {
  const conic::ScaledQcqp* q;
  int evaluations = 0;
};

double objective(const std::vector<double>& y, std::vector<double>& grad, void* data) {
  auto* c = static_cast<Counted*>(data);
  ++c->evaluations;
  const Eigen::Map<const Eigen::VectorXd> yv(y.data(), static_cast<Eigen::Index>(y.size()));
  if (!grad.empty())
    Eigen::Map<Eigen::VectorXd>(grad.data(), static_cast<Eigen::Index>(grad.size())) = c->q->grad_f(yv);
  return c->q->f(yv);
}

double constraint(const std::vector<double>& y, std::vector<double>& grad, void* data) {
  const auto* c = static_cast<Counted*>(data);
  const Eigen::Map<const Eigen::VectorXd> yv(y.data(), static_cast<Eigen::Index>(y.size()));
  if (!grad.empty())
    Eigen::Map<Eigen::VectorXd>(grad.data(), static_cast<Eigen::Index>(grad.size())) = c->q->grad_g(yv);
  return c->q->g(yv);
}

}  // namespace

StepResult NloptSlsqpBackend::solve(const Subproblem& sp) {
  if (sp.kind != ScalarizationKind::kEpsilonConstraint || sp.lin == nullptr) {
    throw Error("nlopt: needs an epsilon-constraint subproblem with a linearization");
  }
  const Linearization& lin = *sp.lin;
  const conic::ScaledQcqp q = conic::scale_qcqp(lin.f1, lin.f2, sp.epsilon);
  if (sp.epsilon <= conic::factor_from_model(lin.f2).floor) {
    return conic::to_step_result(conic::infeasible_step(lin.f2));
  }
  StepResult r;
  const int n = q.dim();
  nlopt::opt opt(nlopt::LD_SLSQP, static_cast<unsigned>(n));
  Counted data{&q, 0};
  opt.set_min_objective(objective, &data);
  opt.add_inequality_constraint(constraint, &data, 1e-12);
  opt.set_xtol_rel(1e-12);
  opt.set_ftol_rel(1e-15);
  opt.set_maxeval(500);
  std::vector<double> y(n, 0.0);
  double fval = 0.0;
  nlopt::result res;
  std::string note;
  try {
    res = opt.optimize(y, fval);
  } catch (const nlopt::roundoff_limited&) {
    // SLSQP's line search hit rounding: y holds its last iterate, usually converged to
    // working precision; reported in the status.
    res = nlopt::ROUNDOFF_LIMITED;
    note = " (roundoff-limited)";
  } catch (const std::exception& e) {
    throw Error(std::string("nlopt: SLSQP failed: ") + e.what());
  }
  const Eigen::Map<const Eigen::VectorXd> yv(y.data(), n);
  if (!yv.allFinite()) throw Error("nlopt: SLSQP returned a non-finite step");
  r.delta = q.to_delta(yv);
  // SLSQP does not return multipliers: least squares on grad f + lambda grad g = 0 when active.
  const Eigen::VectorXd gf = q.grad_f(yv), gg = q.grad_g(yv);
  const bool active = q.g(yv) > -1e-9;
  const double lambda = active && gg.squaredNorm() > 0.0 ? std::max(0.0, -gf.dot(gg) / gg.squaredNorm()) : 0.0;
  r.multiplier = q.to_mu(lambda);
  r.iterations = data.evaluations;
  r.status = (res > 0 ? "optimal (nlopt code " + std::to_string(static_cast<int>(res)) + ")"
                      : "nlopt code " + std::to_string(static_cast<int>(res))) +
             note;
  return r;
}

}  // namespace bivo::solvers
