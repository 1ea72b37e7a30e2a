#pragma once
// The shape both Ipopt adapters share: min f(x) s.t. g(x) <= 0, x in R^n free, started at
// x = 0, dense constraint Jacobian and dense lower-triangular Hessian of the Lagrangian.
// Derived classes supply the functions; this class speaks Ipopt's TNLP protocol and keeps
// the final point and multiplier. Used by the QCQP step backend (`ipopt`) and the
// whole-problem backend (`ipopt-nlp`).
#include <initializer_list>
#include <string>
#include <utility>

#include <IpIpoptApplication.hpp>
#include <IpTNLP.hpp>

#include <Eigen/Core>

namespace bivo::solvers {

class OneConstraintTnlp : public Ipopt::TNLP {
 public:
  using Index = Ipopt::Index;
  using Number = Ipopt::Number;
  using Point = Eigen::Map<const Eigen::VectorXd>;

  Eigen::VectorXd x_final;  // empty until Ipopt finishes
  double lambda_final = 0.0;
  Ipopt::SolverReturn status = Ipopt::INTERNAL_ERROR;

 protected:
  virtual int dim() const = 0;
  // Each returns false where the functions cannot be evaluated (Ipopt then backs off).
  virtual bool objective(const Point& x, double& f) = 0;
  virtual bool objective_gradient(const Point& x, Eigen::Map<Eigen::VectorXd> grad) = 0;
  virtual bool constraint(const Point& x, double& g) = 0;
  virtual bool constraint_gradient(const Point& x, Eigen::Map<Eigen::VectorXd> grad) = 0;
  // sigma * Hessian of f + lambda * Hessian of g; only the lower triangle is read.
  virtual bool lagrangian_hessian(const Point& x, double sigma, double lambda, Eigen::MatrixXd& H) = 0;

 public:
  bool get_nlp_info(Index& n, Index& m, Index& nnz_jac, Index& nnz_h, IndexStyleEnum& style) override;
  bool get_bounds_info(Index n, Number* xl, Number* xu, Index, Number* gl, Number* gu) override;
  bool get_starting_point(Index n, bool, Number* x, bool, Number*, Number*, Index, bool, Number*) override;
  bool eval_f(Index n, const Number* x, bool, Number& f) override;
  bool eval_grad_f(Index n, const Number* x, bool, Number* g) override;
  bool eval_g(Index n, const Number* x, bool, Index, Number* g) override;
  bool eval_jac_g(Index n, const Number* x, bool, Index, Index, Index* rows, Index* cols, Number* v) override;
  bool eval_h(Index n, const Number* x, bool, Number sigma, Index, const Number* lam, bool, Index, Index* rows,
              Index* cols, Number* v) override;
  void finalize_solution(Ipopt::SolverReturn st, Index n, const Number* x, const Number*, const Number*, Index,
                         const Number*, const Number* lam, Number, const Ipopt::IpoptData*,
                         Ipopt::IpoptCalculatedQuantities*) override;

 private:
  Eigen::MatrixXd h_;
};

// An initialized Ipopt application with the options every adapter needs: exact Hessian,
// no banner, and bound_relax_factor = 0 (Debian's Ipopt 3.11 otherwise violates the
// constraint by ~1e-8 relative). Throws bivo::Error naming `who` if initialization fails.
// `extra`: further numeric options, set before initialization.
Ipopt::SmartPtr<Ipopt::IpoptApplication> make_ipopt(const std::string& who, int print_level, double tol, int max_iter,
                                                    std::initializer_list<std::pair<const char*, double>> extra = {});

}  // namespace bivo::solvers
