// The table of backends by name. Only the owner of a backend edits its lines; the conic
// engineer's backends go into the two marked blocks below.
#include "solvers/backend_registry.h"

#include <sstream>

#include "solvers/error.h"
#include "solvers/step/exact_qcqp.h"
#include "solvers/step/gauss_newton.h"
#include "solvers/step/ipm_compressed_backend.h"
#include "solvers/step/ipm_full_backend.h"
#include "solvers/step/ipopt_qcqp_backend.h"
#include "solvers/step/levenberg_marquardt.h"
#include "solvers/step/nlopt_slsqp_backend.h"
#include "solvers/whole/ceres_backend.h"
#include "solvers/whole/ipopt_nlp_backend.h"
// ---- end of conic/NLP backend headers ----

namespace bivo::solvers {
namespace {

template <class Backend, class... Args>
BackendInfo step_backend(const std::string& name, const std::string& description, Args... args) {
  BackendInfo info;
  info.name = name;
  info.description = description;
  info.make_step = [args...] { return std::unique_ptr<StepBackend>(new Backend(args...)); };
  const Backend probe(args...);
  if (probe.name() != name) throw Error("backend registry: '" + name + "' constructs '" + probe.name() + "'");
  info.weighted_sum = probe.supports(ScalarizationKind::kWeightedSum);
  info.epsilon_constraint = probe.supports(ScalarizationKind::kEpsilonConstraint);
  return info;
}

BackendInfo whole_problem_backend(const std::string& name, const std::string& description,
                                  std::function<std::unique_ptr<WholeProblemBackend>()> make) {
  BackendInfo info;
  info.name = name;
  info.description = description;
  info.whole_problem = true;
  const auto probe = make();
  info.weighted_sum = probe->supports(ScalarizationKind::kWeightedSum);
  info.epsilon_constraint = probe->supports(ScalarizationKind::kEpsilonConstraint);
  info.make_whole = std::move(make);
  return info;
}

std::vector<BackendInfo> build_registry() {
  std::vector<BackendInfo> r;
  r.push_back(step_backend<GaussNewtonBackend>(
      "gn", "Gauss-Newton: (H1 + lambda H2) d = -(b1 + lambda b2), LDL^T / min-norm if singular"));
  r.push_back(step_backend<LevenbergMarquardtBackend>(
      "lm", "Levenberg-Marquardt on the weighted sum, Marquardt-scaled damping, acceptance test"));
  r.push_back(step_backend<ExactQcqpBackend>(
      "exact", "exact one-constraint QCQP step: d(mu) = -(H1 + mu H2)^-1 (b1 + mu b2), Newton on mu"));
  r.push_back(whole_problem_backend("ceres", "Ceres trust region on F1 + lambda F2 as one problem over the manifold",
                                    [] { return make_ceres_backend(); }));
  r.push_back(step_backend<IpmFullBackend>("ipm-full",
                                           "own conic IPM on the paper's SOCP (eq. `SOCP in our method`), cones of "
                                           "dimension n+1, active-set Newton polish"));
  r.push_back(step_backend<IpmCompressedBackend>(
      "ipm-compressed", "own conic IPM, cones compressed to 7 by QR/Gram factors, floor outside the cone"));
  r.push_back(step_backend<IpmFullBackend>(
      "ipm-full-nopolish", "ipm-full without the active-set Newton polish: the interior-point iterations alone",
      conic::unpolished_step_ipm_settings()));
  r.push_back(step_backend<IpmCompressedBackend>("ipm-compressed-nopolish",
                                                 "ipm-compressed without the active-set Newton polish",
                                                 conic::unpolished_step_ipm_settings()));
  r.push_back(step_backend<IpoptQcqpBackend>(
      "ipopt", "Ipopt (MUMPS) on the scaled QCQP step, exact Hessian, bound_relax_factor = 0"));
  r.push_back(
      step_backend<NloptSlsqpBackend>("nlopt", "NLopt SLSQP on the QCQP step with scaled variables and functions"));
  r.push_back(whole_problem_backend(
      "ipopt-nlp",
      "Ipopt on min F1 s.t. F2 <= epsilon as one nonlinear problem over the manifold, Gauss-Newton Hessian",
      [] { return make_ipopt_nlp_backend(); }));
  // ---- end of conic/NLP backends ----
  return r;
}

}  // namespace

const std::vector<BackendInfo>& backend_infos() {
  static const std::vector<BackendInfo> registry = build_registry();
  return registry;
}

std::vector<std::string> backend_names() {
  std::vector<std::string> names;
  for (const auto& b : backend_infos()) names.push_back(b.name);
  return names;
}

bool has_backend(const std::string& name) {
  for (const auto& b : backend_infos()) {
    if (b.name == name) return true;
  }
  return false;
}

const BackendInfo& backend_info(const std::string& name) {
  for (const auto& b : backend_infos()) {
    if (b.name == name) return b;
  }
  std::ostringstream msg;
  msg << "unknown solver backend '" << name << "'; valid backends:\n" << backend_help();
  throw Error(msg.str());
}

bool is_whole_problem_backend(const std::string& name) { return backend_info(name).whole_problem; }

std::string backend_help() {
  std::size_t width = 0;
  for (const auto& b : backend_infos()) width = std::max(width, b.name.size());
  std::ostringstream out;
  for (const auto& b : backend_infos()) {
    out << "  " << b.name << std::string(width - b.name.size() + 2, ' ') << b.description << " [";
    if (b.weighted_sum) out << "weighted sum";
    if (b.weighted_sum && b.epsilon_constraint) out << ", ";
    if (b.epsilon_constraint) out << "epsilon-constraint";
    out << (b.whole_problem ? "; whole problem]" : "]") << "\n";
  }
  return out.str();
}

std::unique_ptr<StepBackend> make_step_backend(const std::string& name) {
  const BackendInfo& info = backend_info(name);
  if (!info.make_step) {
    throw Error("backend '" + name + "' solves the whole problem, not one step; use solve() by name");
  }
  return info.make_step();
}

std::unique_ptr<WholeProblemBackend> make_whole_problem_backend(const std::string& name) {
  const BackendInfo& info = backend_info(name);
  if (!info.make_whole) throw Error("backend '" + name + "' is a step backend, not a whole-problem one");
  return info.make_whole();
}

std::string default_backend(ScalarizationKind kind) { return kind == ScalarizationKind::kWeightedSum ? "gn" : "exact"; }

}  // namespace bivo::solvers
