#include "solvers/whole/ipopt_one_constraint.h"

#include "solvers/error.h"

namespace bivo::solvers {

bool OneConstraintTnlp::get_nlp_info(Index& n, Index& m, Index& nnz_jac, Index& nnz_h, IndexStyleEnum& style) {
  n = dim();
  m = 1;
  nnz_jac = n;
  nnz_h = n * (n + 1) / 2;
  style = C_STYLE;
  return true;
}

bool OneConstraintTnlp::get_bounds_info(Index n, Number* xl, Number* xu, Index, Number* gl, Number* gu) {
  for (Index i = 0; i < n; ++i) {
    xl[i] = -2e19;  // Ipopt's "no bound"
    xu[i] = 2e19;
  }
  gl[0] = -2e19;
  gu[0] = 0.0;
  return true;
}

bool OneConstraintTnlp::get_starting_point(Index n, bool, Number* x, bool, Number*, Number*, Index, bool, Number*) {
  Eigen::Map<Eigen::VectorXd>(x, n).setZero();
  return true;
}

bool OneConstraintTnlp::eval_f(Index n, const Number* x, bool, Number& f) { return objective(Point(x, n), f); }

bool OneConstraintTnlp::eval_grad_f(Index n, const Number* x, bool, Number* g) {
  return objective_gradient(Point(x, n), Eigen::Map<Eigen::VectorXd>(g, n));
}

bool OneConstraintTnlp::eval_g(Index n, const Number* x, bool, Index, Number* g) {
  return constraint(Point(x, n), g[0]);
}

bool OneConstraintTnlp::eval_jac_g(Index n, const Number* x, bool, Index, Index, Index* rows, Index* cols, Number* v) {
  if (v == nullptr) {
    for (Index i = 0; i < n; ++i) rows[i] = 0, cols[i] = i;
    return true;
  }
  return constraint_gradient(Point(x, n), Eigen::Map<Eigen::VectorXd>(v, n));
}

bool OneConstraintTnlp::eval_h(Index n, const Number* x, bool, Number sigma, Index, const Number* lam, bool, Index,
                               Index* rows, Index* cols, Number* v) {
  if (v == nullptr) {
    Index k = 0;
    for (Index i = 0; i < n; ++i) {
      for (Index j = 0; j <= i; ++j, ++k) rows[k] = i, cols[k] = j;
    }
    return true;
  }
  if (!lagrangian_hessian(Point(x, n), sigma, lam[0], h_)) return false;
  Index k = 0;
  for (Index i = 0; i < n; ++i) {
    for (Index j = 0; j <= i; ++j, ++k) v[k] = h_(i, j);
  }
  return true;
}

void OneConstraintTnlp::finalize_solution(Ipopt::SolverReturn st, Index n, const Number* x, const Number*,
                                          const Number*, Index, const Number*, const Number* lam, Number,
                                          const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) {
  status = st;
  x_final = Point(x, n);
  lambda_final = lam[0];
}

Ipopt::SmartPtr<Ipopt::IpoptApplication> make_ipopt(const std::string& who, int print_level, double tol, int max_iter,
                                                    std::initializer_list<std::pair<const char*, double>> extra) {
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  app->Options()->SetIntegerValue("print_level", print_level);
  app->Options()->SetStringValue("sb", "yes");
  app->Options()->SetNumericValue("bound_relax_factor", 0.0);
  app->Options()->SetNumericValue("tol", tol);
  app->Options()->SetIntegerValue("max_iter", max_iter);
  app->Options()->SetStringValue("hessian_approximation", "exact");
  for (const auto& [name, value] : extra) app->Options()->SetNumericValue(name, value);
  if (app->Initialize() != Ipopt::Solve_Succeeded) throw Error(who + ": Ipopt initialization failed");
  return app;
}

}  // namespace bivo::solvers
