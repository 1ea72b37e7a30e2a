#pragma once
// Backends by name. Step backends solve one Subproblem per outer iteration; whole-problem
// backends take the nonlinear problem itself. Unknown names -> bivo::Error listing the
// valid ones.
//
//   name            kind           scalarization        what
//   gn              step           weighted sum         Gauss-Newton, eq. `linear system`
//   lm              step           weighted sum         Levenberg-Marquardt (Marquardt scaling)
//   exact           step           epsilon-constraint   exact one-constraint QCQP step, eq. `QCQP`
//   ceres           whole problem  weighted sum         Ceres trust region over the manifold
//   ipm-full        step           epsilon-constraint   own IPM on eq. `SOCP in our method`
//   ipm-compressed  step           epsilon-constraint   own IPM, cones compressed to dimension 7
//   ipopt           step           epsilon-constraint   Ipopt on the QCQP step
//   nlopt           step           epsilon-constraint   NLopt SLSQP on the QCQP step
//   ipopt-nlp       whole problem  epsilon-constraint   Ipopt on eq. `bounded objective form`
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "solvers/step_backend.h"
#include "solvers/whole_problem_backend.h"

namespace bivo::solvers {

struct BackendInfo {
  std::string name;
  std::string description;  // one line, for --help and error messages
  bool whole_problem = false;
  bool weighted_sum = false;        // supports ScalarizationKind::kWeightedSum
  bool epsilon_constraint = false;  // supports ScalarizationKind::kEpsilonConstraint
  // Exactly one of these is set.
  std::function<std::unique_ptr<StepBackend>()> make_step;
  std::function<std::unique_ptr<WholeProblemBackend>()> make_whole;
};

const std::vector<BackendInfo>& backend_infos();  // registration order
std::vector<std::string> backend_names();
bool has_backend(const std::string& name);
bool is_whole_problem_backend(const std::string& name);    // throws on unknown name
const BackendInfo& backend_info(const std::string& name);  // throws on unknown name
// "  gn  Gauss-Newton ... [weighted sum]\n  ..." for --help texts.
std::string backend_help();

std::unique_ptr<StepBackend> make_step_backend(const std::string& name);  // throws if whole-problem
std::unique_ptr<WholeProblemBackend> make_whole_problem_backend(const std::string& name);

// Default backend for a scalarization: "gn" (weighted sum), "exact" (epsilon-constraint).
std::string default_backend(ScalarizationKind kind);

}  // namespace bivo::solvers
