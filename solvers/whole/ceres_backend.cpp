// The "ceres" whole-problem backend; the only file that includes Ceres.
#include "solvers/whole/ceres_backend.h"

#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

#include <ceres/ceres.h>
#include <Eigen/Dense>

#include "solvers/error.h"

namespace bivo::solvers {
namespace {

using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

Eigen::MatrixXd pseudo_inverse(const Eigen::MatrixXd& P) { return P.completeOrthogonalDecomposition().pseudoInverse(); }

// Our Manifold seen by Ceres. For SE(3) the quaternion's sign is kept continuous with x
// (our retract normalizes but may flip it), which Ceres' Plus must be.
class CeresManifoldAdapter final : public ceres::Manifold {
 public:
  explicit CeresManifoldAdapter(const solvers::Manifold& m)
      : m_(m), is_se3_(dynamic_cast<const Se3Manifold*>(&m) != nullptr) {}
  int AmbientSize() const override { return m_.ambient_dim(); }
  int TangentSize() const override { return m_.tangent_dim(); }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override {
    const Eigen::Map<const Eigen::VectorXd> xv(x, AmbientSize());
    const Eigen::Map<const Eigen::VectorXd> dv(delta, TangentSize());
    Eigen::VectorXd y = m_.retract(xv, dv);
    if (is_se3_ && y.tail<4>().dot(xv.tail<4>()) < 0.0) y.tail<4>() *= -1.0;
    Eigen::Map<Eigen::VectorXd>(x_plus_delta, AmbientSize()) = y;
    return y.allFinite();
  }
  bool PlusJacobian(const double* x, double* jacobian) const override {
    const RowMajor P = m_.plus_jacobian(Eigen::Map<const Eigen::VectorXd>(x, AmbientSize()));
    Eigen::Map<RowMajor>(jacobian, AmbientSize(), TangentSize()) = P;
    return true;
  }
  bool Minus(const double* y, const double* x, double* y_minus_x) const override {
    const Eigen::VectorXd d = m_.minus(Eigen::Map<const Eigen::VectorXd>(y, AmbientSize()),
                                       Eigen::Map<const Eigen::VectorXd>(x, AmbientSize()));
    Eigen::Map<Eigen::VectorXd>(y_minus_x, TangentSize()) = d;
    return d.allFinite();
  }
  bool MinusJacobian(const double* x, double* jacobian) const override {
    const RowMajor Pinv = pseudo_inverse(m_.plus_jacobian(Eigen::Map<const Eigen::VectorXd>(x, AmbientSize())));
    Eigen::Map<RowMajor>(jacobian, TangentSize(), AmbientSize()) = Pinv;
    return true;
  }

 private:
  const solvers::Manifold& m_;
  bool is_se3_;
};

// Residual vector sqrt(2) [sqrt(w_1) r_1; sqrt(lambda w_2) r_2]: Ceres minimizes half its
// squared norm, which is then exactly F_1 + lambda F_2. The Jacobian handed to Ceres is
// J_tangent P^+ so that Ceres' product with P (the PlusJacobian) gives J_tangent back.
class WeightedSumCost final : public ceres::CostFunction {
 public:
  WeightedSumCost(BiObjectiveProblem& problem, double lambda, int n1, int n2)
      : problem_(problem), lambda_(lambda), n1_(n1), n2_(n2) {
    set_num_residuals(n1 + n2);
    mutable_parameter_block_sizes()->push_back(problem.manifold().ambient_dim());
  }
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const Manifold& m = problem_.manifold();
    const Eigen::Map<const Eigen::VectorXd> xm(parameters[0], m.ambient_dim());
    const Eigen::VectorXd x = xm;
    const bool want_j = jacobians != nullptr && jacobians[0] != nullptr;
    const ResidualData d1 = problem_.residuals(1, x, want_j);
    const ResidualData d2 = problem_.residuals(2, x, want_j);
    if (d1.r.size() != n1_ || d2.r.size() != n2_ || d1.w.size() != n1_ || d2.w.size() != n2_) return false;
    const Eigen::VectorXd s1 = (2.0 * d1.w.array()).sqrt().matrix();
    const Eigen::VectorXd s2 = (2.0 * lambda_ * d2.w.array()).sqrt().matrix();
    Eigen::Map<Eigen::VectorXd> res(residuals, n1_ + n2_);
    res.head(n1_) = s1.cwiseProduct(d1.r);
    res.tail(n2_) = s2.cwiseProduct(d2.r);
    if (!res.allFinite()) return false;
    // A point where the objectives measure nothing is an evaluation failure to Ceres: the step
    // is refused and the trust region shrinks, instead of F = 0 being accepted there.
    if (problem_.degenerate(x)) return false;
    if (want_j) {
      const int t = m.tangent_dim();
      if (d1.J.rows() != n1_ || d1.J.cols() != t || d2.J.rows() != n2_ || d2.J.cols() != t) return false;
      const Eigen::MatrixXd Pinv = pseudo_inverse(m.plus_jacobian(x));  // t x ambient
      Eigen::Map<RowMajor> J(jacobians[0], n1_ + n2_, m.ambient_dim());
      J.topRows(n1_) = s1.asDiagonal() * d1.J * Pinv;
      J.bottomRows(n2_) = s2.asDiagonal() * d2.J * Pinv;
      if (!J.allFinite()) return false;
    }
    return true;
  }

 private:
  BiObjectiveProblem& problem_;
  double lambda_;
  int n1_, n2_;
};

class RecordingCallback final : public ceres::IterationCallback {
 public:
  RecordingCallback(BiObjectiveProblem& problem, const double* x, int n, double lambda, Summary& summary, int verbosity,
                    int first_iteration)
      : problem_(problem),
        x_(x),
        n_(n),
        lambda_(lambda),
        summary_(summary),
        verbosity_(verbosity),
        offset_(first_iteration) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    if (s.iteration == 0) return ceres::SOLVER_CONTINUE;
    IterationRecord rec;
    rec.iteration = offset_ + s.iteration;
    const auto f = problem_.evaluate(Eigen::Map<const Eigen::VectorXd>(x_, n_));
    rec.f1 = f[0];
    rec.f2 = f[1];
    rec.multiplier = lambda_;
    rec.step_norm = s.step_norm;
    rec.accepted = s.step_is_successful;
    rec.inner_iterations = s.linear_solver_iterations;
    rec.seconds = s.iteration_time_in_seconds;
    rec.x = Eigen::Map<const Eigen::VectorXd>(x_, n_);
    summary_.records.push_back(rec);
    if (verbosity_ > 0) {
      std::fprintf(stderr, "bivo ceres it %3d F1 %.6e F2 %.6e |d| %.3e %s\n", rec.iteration, rec.f1, rec.f2,
                   rec.step_norm, rec.accepted ? "" : "rejected");
    }
    return ceres::SOLVER_CONTINUE;
  }

 private:
  BiObjectiveProblem& problem_;
  const double* x_;
  int n_;
  double lambda_;
  Summary& summary_;
  int verbosity_;
  int offset_;
};

class CeresBackend final : public WholeProblemBackend {
 public:
  std::string name() const override { return "ceres"; }
  bool supports(ScalarizationKind kind) const override { return kind == ScalarizationKind::kWeightedSum; }

  Summary solve(BiObjectiveProblem& problem, const Scalarization& scalarization, Eigen::VectorXd& x,
                const SolverOptions& options) override {
    const auto t0 = std::chrono::steady_clock::now();
    const auto* ws = dynamic_cast<const WeightedSum*>(&scalarization);
    if (ws == nullptr) throw Error("backend 'ceres' supports the weighted sum only, got " + scalarization.describe());
    const Manifold& m = problem.manifold();
    if (x.size() != m.ambient_dim() || !x.allFinite()) {
      std::ostringstream msg;
      msg << "ceres(" << problem.name() << "): x must be finite with " << m.ambient_dim() << " entries, got "
          << x.size();
      throw Error(msg.str());
    }
    Summary summary;
    summary.problem = problem.name();
    summary.backend = name();
    summary.kind = ScalarizationKind::kWeightedSum;
    summary.scalarization = scalarization.describe();

    // Each pass fixes the weights by one linearize() (which also gives a lambda policy its
    // input) and lets Ceres solve the resulting weighted least-squares problem; robust
    // problems re-estimate their weights at the next pass (IRLS). Passes stop when Ceres no
    // longer decreases the re-weighted cost by more than the relative-decrease tolerance or no
    // longer moves x by more than the step tolerance, or when the iteration budget (shared by
    // all passes) is spent; problems with fixed weights stop in the second pass.
    LinearizeOptions lo;
    lo.profile = &summary.phases;
    Linearization lin = problem.linearize(x, lo);
    validate_linearization(lin, m.tangent_dim());
    double lambda = ws->lambda_for(lin);
    const auto f0 = problem.evaluate(x);
    if (!std::isfinite(f0[0]) || !std::isfinite(f0[1])) {
      throw Error("ceres(" + problem.name() + "): objectives at the initial x are not finite");
    }
    summary.initial_f1 = f0[0];
    summary.initial_f2 = f0[1];
    const int n1 = static_cast<int>(problem.residuals(1, x, false).r.size());
    const int n2 = static_cast<int>(problem.residuals(2, x, false).r.size());

    int budget = options.max_iterations;
    int passes_run = 0;
    summary.termination = TerminationReason::kMaxIterations;
    summary.message = "reached max_iterations = " + std::to_string(options.max_iterations);
    ceres::Solver::Summary cs;
    for (int pass = 0; budget > 0; ++pass) {  // every pass spends >= 1 of the budget
      if (pass > 0) {
        lin = problem.linearize(x, lo);
        if (!lin.f1.b.allFinite() || !lin.f2.b.allFinite() || !std::isfinite(lin.f1.a) || !std::isfinite(lin.f2.a)) {
          summary.termination = TerminationReason::kNumericalFailure;
          summary.message = "re-weighting linearization has NaN/Inf entries; x kept";
          break;
        }
        lambda = ws->lambda_for(lin);
      }
      summary.multiplier = lambda;
      ++passes_run;
      std::vector<double> param(x.data(), x.data() + x.size());
      ceres::Problem::Options po;
      po.cost_function_ownership = ceres::TAKE_OWNERSHIP;
      po.manifold_ownership = ceres::TAKE_OWNERSHIP;
      ceres::Problem cp(po);
      cp.AddResidualBlock(new WeightedSumCost(problem, lambda, n1, n2), nullptr, param.data());
      cp.SetManifold(param.data(), new CeresManifoldAdapter(m));

      ceres::Solver::Options so;
      so.minimizer_type = ceres::TRUST_REGION;
      so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
      so.linear_solver_type = ceres::DENSE_QR;
      // Start nearly undamped (a Gauss-Newton step); Ceres' default radius 1e4 would damp the
      // first steps of problems in raw odometry units.
      so.initial_trust_region_radius = 1e12;
      so.max_num_iterations = budget;
      so.function_tolerance = options.relative_decrease_tolerance;
      so.parameter_tolerance = options.step_tolerance;
      so.gradient_tolerance = 1e-30;  // stop on our tolerances, not on Ceres' gradient test
      so.logging_type = ceres::SILENT;
      so.minimizer_progress_to_stdout = false;
      so.num_threads = 1;
      so.update_state_every_iteration = true;
      RecordingCallback callback(problem, param.data(), m.ambient_dim(), lambda, summary, options.verbosity,
                                 static_cast<int>(summary.records.size()));
      so.callbacks.push_back(&callback);
      ceres::Solve(so, &cp, &cs);
      const int used = std::max(0, static_cast<int>(cs.iterations.size()) - 1);
      budget -= std::max(used, 1);
      summary.iterations += used;
      summary.phases.add("residuals", cs.residual_evaluation_time_in_seconds + cs.jacobian_evaluation_time_in_seconds);
      summary.phases.add("subproblem", cs.linear_solver_time_in_seconds);

      const Eigen::VectorXd x_end = Eigen::Map<const Eigen::VectorXd>(param.data(), m.ambient_dim());
      const auto f_end = x_end.allFinite() ? problem.evaluate(x_end) : std::array<double, 2>{NAN, NAN};
      if (!std::isfinite(f_end[0]) || !std::isfinite(f_end[1])) {
        summary.termination = TerminationReason::kNumericalFailure;
        summary.message = "Ceres ended at a NaN/Inf point; x kept at the last good value (" + cs.message + ")";
        break;
      }
      const double moved = m.minus(x_end, x).norm();
      x = x_end;
      if (cs.termination_type == ceres::FAILURE || cs.termination_type == ceres::USER_FAILURE) {
        summary.termination = TerminationReason::kBackendFailure;
        summary.message = cs.message;
        break;
      }
      if (cs.termination_type == ceres::NO_CONVERGENCE) continue;  // budget decides
      const bool no_decrease = cs.initial_cost - cs.final_cost <= options.relative_decrease_tolerance * cs.initial_cost;
      if (pass > 0 && (moved < options.step_tolerance || no_decrease)) {
        summary.termination =
            moved < options.step_tolerance ? TerminationReason::kStepTolerance : TerminationReason::kRelativeDecrease;
        summary.message = std::to_string(passes_run) + " weight passes; last: " + cs.message;
        break;
      }
    }
    const auto f_final = problem.evaluate(x);
    summary.final_f1 = f_final[0];
    summary.final_f2 = f_final[1];
    summary.total_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    summary.phases.add("other", std::max(0.0, summary.total_seconds - summary.phases.total_seconds()));
    if (options.profile) options.profile->merge(summary.phases);
    return summary;
  }
};

}  // namespace

std::unique_ptr<WholeProblemBackend> make_ceres_backend() { return std::make_unique<CeresBackend>(); }

}  // namespace bivo::solvers
