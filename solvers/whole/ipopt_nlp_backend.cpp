// The "ipopt-nlp" whole-problem backend (see the header for the formulation).
#include "solvers/whole/ipopt_nlp_backend.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include <IpSolveStatistics.hpp>

#include <Eigen/Dense>

#include "solvers/error.h"
#include "solvers/whole/ipopt_one_constraint.h"

namespace bivo::solvers {
namespace {

// F_j, its gradient and Gauss-Newton Hessian in the tangent coordinates d around x_c.
struct Evaluation {
  Eigen::VectorXd d;
  bool ok = false;
  double F1 = 0.0, F2 = 0.0;
  Eigen::VectorXd g1, g2;  // gradients in d
  Eigen::MatrixXd H1, H2;  // Gauss-Newton Hessians in d
};

// d (perturbation at x(d)) / d (d): the chain factor T(d) of the header. Identity on R^n;
// otherwise central differences of the inverse retraction around x(d) (step 1e-6: error
// O(h^2) from curvature plus O(eps/h) roundoff, ~1e-10), exactly I at d = 0.
Eigen::MatrixXd tangent_chain(const Manifold& m, const Eigen::VectorXd& xc, const Eigen::VectorXd& d,
                              const Eigen::VectorXd& x) {
  const int n = m.tangent_dim();
  if (dynamic_cast<const EuclideanManifold*>(&m) != nullptr || d.squaredNorm() == 0.0) {
    return Eigen::MatrixXd::Identity(n, n);
  }
  const double h = 1e-6;
  Eigen::MatrixXd T(n, n);
  for (int k = 0; k < n; ++k) {
    Eigen::VectorXd e = Eigen::VectorXd::Zero(n);
    e(k) = h;
    T.col(k) = (m.minus(m.retract(xc, d + e), x) - m.minus(m.retract(xc, d - e), x)) / (2.0 * h);
  }
  return T;
}

// Scaled: f = F_1 / f_scale, g = F_2 / epsilon - 1 <= 0, in tangent coordinates d.
class EpsilonNlp final : public OneConstraintTnlp {
 public:
  EpsilonNlp(BiObjectiveProblem& problem, const Eigen::VectorXd& xc, double epsilon, double f_scale)
      : problem_(problem), xc_(xc), epsilon_(epsilon), f_scale_(f_scale) {}

 protected:
  int dim() const override { return problem_.manifold().tangent_dim(); }
  bool objective(const Point& d, double& f) override {
    const Evaluation& e = at(d);
    f = e.F1 / f_scale_;
    return e.ok;
  }
  bool objective_gradient(const Point& d, Eigen::Map<Eigen::VectorXd> grad) override {
    const Evaluation& e = at(d);
    grad = e.g1 / f_scale_;
    return e.ok;
  }
  bool constraint(const Point& d, double& g) override {
    const Evaluation& e = at(d);
    g = e.F2 / epsilon_ - 1.0;
    return e.ok;
  }
  bool constraint_gradient(const Point& d, Eigen::Map<Eigen::VectorXd> grad) override {
    const Evaluation& e = at(d);
    grad = e.g2 / epsilon_;
    return e.ok;
  }
  bool lagrangian_hessian(const Point& d, double sigma, double lambda, Eigen::MatrixXd& H) override {
    const Evaluation& e = at(d);
    H = sigma / f_scale_ * e.H1 + lambda / epsilon_ * e.H2;
    return e.ok;
  }

 private:
  // Ipopt asks for f, g and their derivatives at the same point in separate calls; one
  // residual evaluation serves them all.
  const Evaluation& at(const Point& d) {
    if (cache_.d.size() == d.size() && cache_.d == d) return cache_;
    cache_ = Evaluation();
    cache_.d = d;
    if (!d.allFinite()) return cache_;
    const Manifold& m = problem_.manifold();
    const Eigen::VectorXd xd = m.retract(xc_, cache_.d);
    if (!xd.allFinite()) return cache_;
    const Eigen::MatrixXd T = tangent_chain(m, xc_, cache_.d, xd);
    const int t = m.tangent_dim();
    for (int j = 1; j <= 2; ++j) {
      const ResidualData rd = problem_.residuals(j, xd, true);
      if (rd.J.rows() != rd.r.size() || rd.J.cols() != t || rd.w.size() != rd.r.size()) {
        std::ostringstream msg;
        msg << "ipopt-nlp(" << problem_.name() << "): residuals(" << j << ") returned r " << rd.r.size() << ", J "
            << rd.J.rows() << "x" << rd.J.cols() << ", w " << rd.w.size() << " (tangent dim " << t << ")";
        throw Error(msg.str());
      }
      const Eigen::MatrixXd JT = rd.J * T;
      const Eigen::VectorXd wr = rd.w.cwiseProduct(rd.r);
      const double F = rd.r.dot(wr);
      Eigen::VectorXd g = 2.0 * JT.transpose() * wr;
      Eigen::MatrixXd H = 2.0 * JT.transpose() * rd.w.asDiagonal() * JT;
      (j == 1 ? cache_.F1 : cache_.F2) = F;
      (j == 1 ? cache_.g1 : cache_.g2) = std::move(g);
      (j == 1 ? cache_.H1 : cache_.H2) = std::move(H);
    }
    cache_.ok = std::isfinite(cache_.F1) && std::isfinite(cache_.F2) && cache_.g1.allFinite() &&
                cache_.g2.allFinite() && cache_.H1.allFinite() && cache_.H2.allFinite();
    return cache_;
  }

  BiObjectiveProblem& problem_;
  Eigen::VectorXd xc_;
  double epsilon_;
  double f_scale_;
  Evaluation cache_;
};

const char* ipopt_status_name(Ipopt::SolverReturn s) {
  switch (s) {
    case Ipopt::SUCCESS:
      return "optimal";
    case Ipopt::STOP_AT_ACCEPTABLE_POINT:
      return "acceptable";
    case Ipopt::MAXITER_EXCEEDED:
      return "max iterations";
    case Ipopt::LOCAL_INFEASIBILITY:
      return "locally infeasible";
    case Ipopt::STOP_AT_TINY_STEP:
      return "tiny step";
    case Ipopt::RESTORATION_FAILURE:
      return "restoration failure";
    case Ipopt::ERROR_IN_STEP_COMPUTATION:
      return "error in step computation";
    case Ipopt::INVALID_NUMBER_DETECTED:
      return "invalid number";
    default:
      return "failure";
  }
}

class IpoptNlpBackend final : public WholeProblemBackend {
 public:
  std::string name() const override { return "ipopt-nlp"; }
  bool supports(ScalarizationKind kind) const override { return kind == ScalarizationKind::kEpsilonConstraint; }

  Summary solve(BiObjectiveProblem& problem, const Scalarization& scalarization, Eigen::VectorXd& x,
                const SolverOptions& options) override {
    const auto t0 = std::chrono::steady_clock::now();
    const auto* ec = dynamic_cast<const EpsilonConstraint*>(&scalarization);
    if (ec == nullptr) {
      throw Error("backend 'ipopt-nlp' supports the epsilon-constraint only, got " + scalarization.describe());
    }
    const Manifold& m = problem.manifold();
    if (x.size() != m.ambient_dim() || !x.allFinite()) {
      std::ostringstream msg;
      msg << "ipopt-nlp(" << problem.name() << "): x must be finite with " << m.ambient_dim() << " entries, got "
          << x.size();
      throw Error(msg.str());
    }
    Summary summary;
    summary.problem = problem.name();
    summary.backend = name();
    summary.kind = ScalarizationKind::kEpsilonConstraint;
    summary.scalarization = scalarization.describe();
    summary.termination = TerminationReason::kMaxIterations;
    summary.message = "reached max_iterations = " + std::to_string(options.max_iterations);

    LinearizeOptions lo;
    lo.profile = &summary.phases;
    const auto f0 = problem.evaluate(x);
    if (!std::isfinite(f0[0]) || !std::isfinite(f0[1])) {
      throw Error("ipopt-nlp(" + problem.name() + "): objectives at the initial x are not finite");
    }
    summary.initial_f1 = f0[0];
    summary.initial_f2 = f0[1];

    // Passes: re-centre and re-linearize (weights, epsilon policy) between Ipopt runs. A
    // pass that moves x by less than Ipopt's reach (relative 1e-7 of the first move, or the
    // step tolerance) ends the solve: a further pass would only repeat Ipopt's tolerance.
    int budget = std::max(1, options.max_iterations);
    double first_move = -1.0;
    bool last_feasible = true;
    for (int pass = 0; budget > 0 && pass < 20; ++pass) {
      const auto t_pass = std::chrono::steady_clock::now();
      const Linearization lin = problem.linearize(x, lo);
      validate_linearization(lin, m.tangent_dim());
      const double epsilon = ec->epsilon_for(lin);
      summary.epsilon = epsilon;
      if (!(epsilon > 0.0)) {
        // F_2 <= 0 is only reachable where every weighted residual of F_2 vanishes; the scaled
        // constraint F_2 / epsilon would divide by zero.
        summary.termination = TerminationReason::kBackendFailure;
        summary.feasible = false;
        summary.multiplier = std::numeric_limits<double>::infinity();
        summary.message = "epsilon = 0: ipopt-nlp needs epsilon > 0";
        last_feasible = false;
        break;
      }
      const double f_scale = std::max(lin.f1.a, 1e-300);

      Ipopt::SmartPtr<Ipopt::IpoptApplication> app =
          make_ipopt("ipopt-nlp", options.verbosity > 1 ? 5 : 0, 1e-10, budget,
                     {{"constr_viol_tol", 1e-10}, {"acceptable_tol", 1e-8}});
      auto* raw = new EpsilonNlp(problem, x, epsilon, f_scale);
      Ipopt::SmartPtr<Ipopt::TNLP> nlp = raw;
      const auto t_solve = std::chrono::steady_clock::now();
      app->OptimizeTNLP(nlp);
      summary.phases.add("subproblem",
                         std::chrono::duration<double>(std::chrono::steady_clock::now() - t_solve).count());
      Ipopt::SmartPtr<Ipopt::SolveStatistics> stats = app->Statistics();
      const int used = Ipopt::IsValid(stats) ? std::max(1, static_cast<int>(stats->IterationCount())) : 1;
      budget -= used;
      summary.iterations += used;

      const Ipopt::SolverReturn st = raw->status;
      const bool finite = raw->x_final.size() == m.tangent_dim() && raw->x_final.allFinite();
      Eigen::VectorXd x_new = finite ? m.retract(x, raw->x_final) : x;
      auto f_new = x_new.allFinite() ? problem.evaluate(x_new) : std::array<double, 2>{NAN, NAN};
      if (!std::isfinite(f_new[0]) || !std::isfinite(f_new[1])) {
        summary.termination = TerminationReason::kNumericalFailure;
        summary.message = std::string("Ipopt ended at a NaN/Inf point (") + ipopt_status_name(st) + "); x kept";
        last_feasible = false;
        break;
      }
      const bool infeasible = st == Ipopt::LOCAL_INFEASIBILITY;
      const bool solved = st == Ipopt::SUCCESS || st == Ipopt::STOP_AT_ACCEPTABLE_POINT;
      if (infeasible) {
        // Ipopt's restoration phase ends at a point of least violation: keep it when it lowers
        // F_2 (the nonlinear analogue of the step backends' min m_2 step), else the start.
        if (!(f_new[1] < problem.evaluate(x)[1])) x_new = x, f_new = problem.evaluate(x);
      }
      if (st == Ipopt::MAXITER_EXCEEDED) {
        // An interior-point iterate cut off by the budget need not be better than where the
        // pass started: keep it only when it lowers the violation of F_2 <= epsilon, or stays
        // feasible and lowers F_1 (a filter test); else the pass failed and x stays.
        const auto f_start = problem.evaluate(x);
        const double v_new = std::max(0.0, f_new[1] - epsilon), v_start = std::max(0.0, f_start[1] - epsilon);
        if (!(v_new < v_start || (v_new == 0.0 && v_start == 0.0 && f_new[0] < f_start[0]))) {
          summary.termination = TerminationReason::kBackendFailure;
          std::ostringstream msg;
          msg << "Ipopt's iteration budget ran out at a point worse than its start (F = " << f_new[0] << ", "
              << f_new[1] << " against " << f_start[0] << ", " << f_start[1] << ", epsilon " << epsilon << "); x kept";
          summary.message = msg.str();
          last_feasible = v_start == 0.0;
          break;
        }
      }
      const double moved = m.minus(x_new, x).norm();
      x = x_new;
      summary.multiplier =
          infeasible ? std::numeric_limits<double>::infinity() : std::max(0.0, raw->lambda_final) * f_scale / epsilon;
      last_feasible = !infeasible;

      IterationRecord rec;
      rec.iteration = pass + 1;
      rec.f1 = f_new[0];
      rec.f2 = f_new[1];
      rec.multiplier = summary.multiplier;
      rec.epsilon = epsilon;
      rec.step_norm = moved;
      rec.accepted = true;
      rec.feasible = !infeasible;
      rec.inner_iterations = used;
      rec.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_pass).count();
      rec.x = x;
      summary.records.push_back(rec);
      if (options.verbosity > 0) {
        std::fprintf(stderr, "bivo ipopt-nlp pass %2d F1 %.6e F2 %.6e mu %.4e |d| %.3e ipopt %s (%d it)\n",
                     rec.iteration, rec.f1, rec.f2, rec.multiplier, moved, ipopt_status_name(st), used);
      }

      if (infeasible) {
        summary.termination = TerminationReason::kBackendFailure;
        std::ostringstream msg;
        msg << "epsilon infeasible: Ipopt found no x with F_2 <= epsilon = " << epsilon << " (least F_2 reached "
            << f_new[1] << ")";
        summary.message = msg.str();
        break;
      }
      if (!solved && st != Ipopt::MAXITER_EXCEEDED) {
        summary.termination = TerminationReason::kBackendFailure;
        summary.message = std::string("Ipopt: ") + ipopt_status_name(st);
        break;
      }
      if (st == Ipopt::MAXITER_EXCEEDED) continue;  // the budget decides
      if (first_move < 0.0) first_move = moved;
      if (pass > 0 && moved <= std::max(options.step_tolerance, 1e-7 * (1.0 + first_move))) {
        summary.termination = TerminationReason::kStepTolerance;
        summary.message = std::to_string(pass + 1) + " passes; Ipopt " + ipopt_status_name(st) +
                          "; last pass moved x by " + std::to_string(moved);
        break;
      }
    }
    const auto f_final = problem.evaluate(x);
    summary.final_f1 = f_final[0];
    summary.final_f2 = f_final[1];
    summary.feasible = last_feasible && f_final[1] <= summary.epsilon * (1.0 + 1e-6) + 1e-300;
    summary.total_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    summary.phases.add("other", std::max(0.0, summary.total_seconds - summary.phases.total_seconds()));
    if (options.profile) options.profile->merge(summary.phases);
    return summary;
  }
};

}  // namespace

std::unique_ptr<WholeProblemBackend> make_ipopt_nlp_backend() { return std::make_unique<IpoptNlpBackend>(); }

}  // namespace bivo::solvers
