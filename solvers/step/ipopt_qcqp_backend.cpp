#include "solvers/step/ipopt_qcqp_backend.h"

#include <cmath>
#include <limits>

#include <IpIpoptApplication.hpp>
#include <IpSolveStatistics.hpp>
#include <IpTNLP.hpp>

#include <Eigen/Dense>

#include "solvers/conic/qcqp_socp.h"
#include "solvers/conic/scaled_qcqp.h"
#include "solvers/error.h"

namespace bivo::solvers {

namespace {

using Ipopt::Index;
using Ipopt::Number;

// min f(y) s.t. g(y) <= 0, y free; Hessian of the Lagrangian sigma H1~/s1 + lambda H2~/s2
// (times 2), dense lower triangle.
class QcqpTnlp final : public Ipopt::TNLP {
 public:
  explicit QcqpTnlp(const conic::ScaledQcqp& q) : q_(q) {}
  Eigen::VectorXd y;
  double lambda = 0.0;
  Ipopt::SolverReturn status = Ipopt::INTERNAL_ERROR;

  bool get_nlp_info(Index& n, Index& m, Index& nnz_jac, Index& nnz_h, IndexStyleEnum& style) override {
    n = q_.dim();
    m = 1;
    nnz_jac = n;
    nnz_h = n * (n + 1) / 2;
    style = C_STYLE;
    return true;
  }
  bool get_bounds_info(Index n, Number* xl, Number* xu, Index, Number* gl, Number* gu) override {
    for (Index i = 0; i < n; ++i) {
      xl[i] = -2e19;
      xu[i] = 2e19;
    }
    gl[0] = -2e19;
    gu[0] = 0.0;
    return true;
  }
  bool get_starting_point(Index n, bool, Number* x, bool, Number*, Number*, Index, bool, Number*) override {
    for (Index i = 0; i < n; ++i) x[i] = 0.0;
    return true;
  }
  bool eval_f(Index n, const Number* x, bool, Number& f) override {
    f = q_.f(Eigen::Map<const Eigen::VectorXd>(x, n));
    return true;
  }
  bool eval_grad_f(Index n, const Number* x, bool, Number* g) override {
    Eigen::Map<Eigen::VectorXd>(g, n) = q_.grad_f(Eigen::Map<const Eigen::VectorXd>(x, n));
    return true;
  }
  bool eval_g(Index n, const Number* x, bool, Index, Number* g) override {
    g[0] = q_.g(Eigen::Map<const Eigen::VectorXd>(x, n));
    return true;
  }
  bool eval_jac_g(Index n, const Number* x, bool, Index, Index, Index* rows, Index* cols, Number* v) override {
    if (v == nullptr) {
      for (Index i = 0; i < n; ++i) rows[i] = 0, cols[i] = i;
    } else {
      Eigen::Map<Eigen::VectorXd>(v, n) = q_.grad_g(Eigen::Map<const Eigen::VectorXd>(x, n));
    }
    return true;
  }
  bool eval_h(Index n, const Number*, bool, Number sigma, Index, const Number* lam, bool, Index, Index* rows,
              Index* cols, Number* v) override {
    Index k = 0;
    for (Index i = 0; i < n; ++i) {
      for (Index j = 0; j <= i; ++j, ++k) {
        if (v == nullptr) {
          rows[k] = i;
          cols[k] = j;
        } else {
          v[k] = 2.0 * (sigma * q_.H1(i, j) / q_.s1 + lam[0] * q_.H2(i, j) / q_.s2);
        }
      }
    }
    return true;
  }
  void finalize_solution(Ipopt::SolverReturn st, Index n, const Number* x, const Number*, const Number*, Index,
                         const Number*, const Number* lam, Number, const Ipopt::IpoptData*,
                         Ipopt::IpoptCalculatedQuantities*) override {
    status = st;
    y = Eigen::Map<const Eigen::VectorXd>(x, n);
    lambda = lam[0];
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
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  app->Options()->SetIntegerValue("print_level", 0);
  app->Options()->SetStringValue("sb", "yes");
  app->Options()->SetNumericValue("bound_relax_factor", 0.0);
  app->Options()->SetNumericValue("tol", 1e-12);
  app->Options()->SetIntegerValue("max_iter", 200);
  app->Options()->SetStringValue("hessian_approximation", "exact");
  if (app->Initialize() != Ipopt::Solve_Succeeded) throw Error("ipopt: initialization failed");
  auto* raw = new QcqpTnlp(q);
  Ipopt::SmartPtr<Ipopt::TNLP> nlp = raw;
  const Ipopt::ApplicationReturnStatus st = app->OptimizeTNLP(nlp);
  if (raw->y.size() != q.dim() || !raw->y.allFinite()) {
    throw Error("ipopt: no finite solution (status " + std::to_string(static_cast<int>(st)) + ")");
  }
  r.delta = q.to_delta(raw->y);
  r.multiplier = q.to_mu(std::max(0.0, raw->lambda));
  Ipopt::SmartPtr<Ipopt::SolveStatistics> stats = app->Statistics();
  r.iterations = Ipopt::IsValid(stats) ? stats->IterationCount() : 0;
  r.status = (st == Ipopt::Solve_Succeeded || st == Ipopt::Solved_To_Acceptable_Level)
                 ? std::string(st == Ipopt::Solve_Succeeded ? "optimal" : "acceptable")
                 : "ipopt status " + std::to_string(static_cast<int>(st));
  return r;
}

}  // namespace bivo::solvers
