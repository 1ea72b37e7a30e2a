#include "solvers/pareto.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

#include "solvers/backend_registry.h"
#include "solvers/error.h"
#include "solvers/outer_loop.h"
#include "solvers/scalarization.h"

namespace bivo::solvers {
namespace {

ParetoPoint point_from(const Summary& s, const Eigen::VectorXd& x, double parameter) {
  ParetoPoint p;
  p.f1 = s.final_f1;
  p.f2 = s.final_f2;
  p.x = x;
  p.kind = s.kind;
  p.parameter = parameter;
  p.multiplier = s.multiplier;
  p.iterations = s.iterations;
  p.converged = s.converged();
  p.feasible = s.feasible;
  return p;
}

void finish(ParetoFront& front) {
  front.points = nondominated(front.all);
  front.dropped = static_cast<int>(front.all.size() - front.points.size());
}

void check_common(const BiObjectiveProblem& problem, const Eigen::VectorXd& x0, const ParetoOptions& options) {
  if (options.points < 2) throw Error("Pareto sweep: need at least 2 points, got " + std::to_string(options.points));
  if (x0.size() != problem.manifold().ambient_dim() || !x0.allFinite()) {
    throw Error("Pareto sweep: x0 must be finite with " + std::to_string(problem.manifold().ambient_dim()) +
                " entries, got " + std::to_string(x0.size()));
  }
}

}  // namespace

void check_lambda_range(double lambda_min, double lambda_max) {
  if (!(lambda_min > 0.0) || !(lambda_max > lambda_min) || !std::isfinite(lambda_max)) {
    std::ostringstream msg;
    msg << "Pareto lambda sweep: need 0 < lambda_min < lambda_max < inf, got [" << lambda_min << ", " << lambda_max
        << "]";
    throw Error(msg.str());
  }
}

ParetoFront sweep_lambda(BiObjectiveProblem& problem, const Eigen::VectorXd& x0, const ParetoOptions& options) {
  check_common(problem, x0, options);
  check_lambda_range(options.lambda_min, options.lambda_max);
  const std::string backend =
      options.backend.empty() ? default_backend(ScalarizationKind::kWeightedSum) : options.backend;
  ParetoFront front;
  const Manifold& manifold = problem.manifold();
  Eigen::VectorXd x = x0;
  LinearizationCarry carry;  // the previous point's last linearization
  const double ratio = std::log(options.lambda_max / options.lambda_min);
  for (int i = 0; i < options.points; ++i) {
    const double lambda = options.lambda_min * std::exp(ratio * double(i) / double(options.points - 1));
    // Warm start: the previous point, or the secant prediction from the two before.
    std::optional<Eigen::VectorXd> predicted;
    const std::size_t n = front.all.size();
    if (options.secant_predictor && n >= 2 && front.all[n - 1].converged && front.all[n - 2].converged) {
      const Eigen::VectorXd secant = manifold.minus(front.all[n - 1].x, front.all[n - 2].x);
      if (secant.allFinite() && secant.norm() > 2.0 * options.solver.step_tolerance) {
        Eigen::VectorXd start = manifold.retract(x, secant);
        if (start.allFinite()) predicted = std::move(start);
      }
    }
    if (predicted) {
      Eigen::VectorXd xp = *predicted;
      std::optional<Summary> s;
      try {
        s = solve(problem, WeightedSum(lambda), backend, xp, options.solver, &carry);
      } catch (const Error&) {
        // e.g. objectives not finite at the predicted x: fall back to the plain warm start.
      }
      if (s && s->termination != TerminationReason::kNumericalFailure) {
        x = xp;
        front.all.push_back(point_from(*s, x, lambda));
        continue;
      }
    }
    // Warm start where the previous point last linearized: its first step then needs no
    // linearization of its own (LinearizationCarry). After a failed predicted solve the
    // carry holds that solve's last linearization, not the previous point's: the point then
    // starts from the previous point's solution, as without a prediction.
    if (predicted) carry.lin.reset();
    if (carry.lin) x = carry.x;
    const Summary s = solve(problem, WeightedSum(lambda), backend, x, options.solver, &carry);
    front.all.push_back(point_from(s, x, lambda));
  }
  finish(front);
  return front;
}

ParetoFront sweep_epsilon(BiObjectiveProblem& problem, const Eigen::VectorXd& x0, const ParetoOptions& options) {
  check_common(problem, x0, options);
  const std::string backend =
      options.backend.empty() ? default_backend(ScalarizationKind::kEpsilonConstraint) : options.backend;
  // The range's ends: F_1's minimizer (weighted sum, lambda = 0) and F_2's minimum (the exact
  // step with epsilon = 0 is the m_2-minimizer, ties broken by m_1).
  Eigen::VectorXd x_f1 = x0;
  const Summary s1 = solve(problem, WeightedSum(0.0), "gn", x_f1, options.solver);
  Eigen::VectorXd x_f2 = x0;
  const Summary s2 = solve(problem, EpsilonConstraint(0.0), "exact", x_f2, options.solver);
  ParetoFront front;
  front.f2_at_f1_min = s1.final_f2;
  front.f2_min = s2.final_f2;
  if (!(front.f2_at_f1_min >= front.f2_min)) {
    std::ostringstream msg;
    msg << "Pareto epsilon sweep: F_2 at the F_1-minimizer (" << front.f2_at_f1_min << ") is below min F_2 ("
        << front.f2_min << "); the extreme solves did not converge";
    throw Error(msg.str());
  }
  // From the loose end (the F_1-minimizer) towards the tight one, warm-starting each point
  // where the previous one last linearized (as in sweep_lambda).
  Eigen::VectorXd x = x_f1;
  LinearizationCarry carry;
  for (int i = 0; i < options.points; ++i) {
    const double t = double(i) / double(options.points - 1);
    const double eps = front.f2_at_f1_min + t * (front.f2_min - front.f2_at_f1_min);
    if (carry.lin) x = carry.x;
    const Summary s = solve(problem, EpsilonConstraint(eps), backend, x, options.solver, &carry);
    front.all.push_back(point_from(s, x, eps));
  }
  finish(front);
  return front;
}

bool dominates(const ParetoPoint& a, const ParetoPoint& b) {
  return a.f1 <= b.f1 && a.f2 <= b.f2 && (a.f1 < b.f1 || a.f2 < b.f2);
}

std::vector<ParetoPoint> nondominated(const std::vector<ParetoPoint>& points) {
  std::vector<ParetoPoint> out;
  for (std::size_t i = 0; i < points.size(); ++i) {
    bool keep = std::isfinite(points[i].f1) && std::isfinite(points[i].f2);
    for (std::size_t j = 0; j < points.size() && keep; ++j) {
      if (j == i) continue;
      if (dominates(points[j], points[i])) keep = false;
      // exact duplicates: keep the first occurrence only
      if (j < i && points[j].f1 == points[i].f1 && points[j].f2 == points[i].f2) keep = false;
    }
    if (keep) out.push_back(points[i]);
  }
  std::sort(out.begin(), out.end(), [](const ParetoPoint& a, const ParetoPoint& b) { return a.f1 < b.f1; });
  return out;
}

std::optional<std::size_t> knee_index(const std::vector<ParetoPoint>& front) {
  if (front.size() < 3) return std::nullopt;
  double f1_min = front[0].f1, f1_max = front[0].f1, f2_min = front[0].f2, f2_max = front[0].f2;
  for (const auto& p : front) {
    f1_min = std::min(f1_min, p.f1);
    f1_max = std::max(f1_max, p.f1);
    f2_min = std::min(f2_min, p.f2);
    f2_max = std::max(f2_max, p.f2);
  }
  if (!(f1_max > f1_min) || !(f2_max > f2_min)) return std::nullopt;
  const auto n1 = [&](double v) { return (v - f1_min) / (f1_max - f1_min); };
  const auto n2 = [&](double v) { return (v - f2_min) / (f2_max - f2_min); };
  // Chord between the extremes A (least F_1) and B (least F_2), normalized.
  const auto ia = std::min_element(front.begin(), front.end(), [](auto& a, auto& b) { return a.f1 < b.f1; });
  const auto ib = std::min_element(front.begin(), front.end(), [](auto& a, auto& b) { return a.f2 < b.f2; });
  const double ax = n1(ia->f1), ay = n2(ia->f2), bx = n1(ib->f1), by = n2(ib->f2);
  const double len = std::hypot(bx - ax, by - ay);
  if (!(len > 0.0)) return std::nullopt;
  std::optional<std::size_t> best;
  double best_dist = -1.0;
  for (std::size_t i = 0; i < front.size(); ++i) {
    const double px = n1(front[i].f1), py = n2(front[i].f2);
    const double dist = std::abs((bx - ax) * (ay - py) - (ax - px) * (by - ay)) / len;
    if (dist > best_dist) {
      best_dist = dist;
      best = i;
    }
  }
  return best;
}

double hypervolume(const std::vector<ParetoPoint>& points, double ref_f1, double ref_f2) {
  if (!std::isfinite(ref_f1) || !std::isfinite(ref_f2)) {
    std::ostringstream msg;
    msg << "hypervolume: reference point must be finite, got (" << ref_f1 << ", " << ref_f2 << ")";
    throw Error(msg.str());
  }
  std::vector<ParetoPoint> inside;
  for (const auto& p : points) {
    if (p.f1 < ref_f1 && p.f2 < ref_f2) inside.push_back(p);
  }
  const std::vector<ParetoPoint> front = nondominated(inside);  // f1 ascending, f2 descending
  double area = 0.0, upper_f2 = ref_f2;
  for (const auto& p : front) {
    area += (ref_f1 - p.f1) * (upper_f2 - p.f2);
    upper_f2 = p.f2;
  }
  return area;
}

}  // namespace bivo::solvers
