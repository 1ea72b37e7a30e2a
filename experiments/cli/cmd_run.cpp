// `bivo run SEQUENCE_DIR --method M [--backend B] ...`: frame-to-frame odometry over one TUM
// sequence; writes the TUM trajectory and a per-pair log, ends stdout with the run line
// "frames=N median_ms=X mean_ms=Y failures=K".
#include <filesystem>
#include <iostream>
#include <memory>

#include "experiments/cli/commands.h"
#include "experiments/sequence_runner.h"
#include "odometry/odometry_methods.h"
#include "odometry/io/trajectory.h"
#include "solvers/backend_registry.h"
#include "solvers/error.h"

namespace bivo::experiments::cli {

namespace {

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

}  // namespace

void add_run_command(CLI::App& app) {
  struct Args {
    RunRequest request;
    std::optional<double> lambda, eps, phi;
    std::string output, log;
    int levels = 4;
  };
  auto a = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("run", "Frame-to-frame RGB-D odometry over one TUM sequence");
  cmd->add_option("sequence", a->request.sequence_dir,
                  "TUM sequence folder (rgb.txt + depth.txt or associations.txt; groundtruth.txt optional)")
      ->required();
  cmd->add_option("--method", a->request.tracker.method, "one of: " + join(odometry::method_names()))
      ->required();
  cmd->add_option("--backend", a->request.tracker.backend,
                  "solver backend (default: gn for weighted-sum methods, exact for bounded):\n" +
                      solvers::backend_help());
  cmd->add_option("--lambda", a->lambda, "method fixed: the weight lambda of F_I + lambda F_D [gray^2/m^2]");
  cmd->add_option("--eps", a->eps,
                  "method bounded: fixed bound on F_D per unit weight [m^2] instead of the pi(D) rule");
  cmd->add_option("--phi", a->phi, "method weighted: the constant phi of eq. `eq to calculate lambda`");
  cmd->add_option("--levels", a->levels, "pyramid levels")->capture_default_str();
  cmd->add_option("--first-frame", a->request.first_frame, "index of the first associated frame to process")
      ->capture_default_str();
  cmd->add_option("--max-frames", a->request.max_frames, "process at most N frames (-1: all)")
      ->capture_default_str();
  cmd->add_option("--output", a->output, "estimated trajectory (TUM format, one pose per processed frame)");
  cmd->add_option("--log", a->log, "per-pair CSV (timings, lambda/epsilon, objectives, errors vs ground truth)");
  cmd->footer("Ends stdout with: frames=N median_ms=X mean_ms=Y failures=K (time per pair, loading excluded).");
  cmd->callback([a] {
    RunRequest req = a->request;
    const odometry::Method method = odometry::parse_method(req.tracker.method);
    if (a->lambda) {
      if (method != odometry::Method::kFixed) {
        throw Error("--lambda applies to method 'fixed' only (method is '" + req.tracker.method + "')");
      }
      req.tracker.policy.lambda = *a->lambda;
    }
    if (a->eps) {
      if (method != odometry::Method::kBounded) {
        throw Error("--eps applies to method 'bounded' only (method is '" + req.tracker.method + "')");
      }
      req.tracker.policy.eps = *a->eps;
    }
    if (a->phi) {
      if (method != odometry::Method::kWeighted) {
        throw Error("--phi applies to method 'weighted' only (method is '" + req.tracker.method + "')");
      }
      req.tracker.policy.phi = *a->phi;
    }
    req.tracker.levels = a->levels;
    // Fail before the run, not after it, when an output cannot be written.
    for (const std::string* path : {&a->output, &a->log}) {
      if (path->empty()) continue;
      const auto parent = std::filesystem::absolute(*path).parent_path();
      if (!std::filesystem::is_directory(parent)) {
        throw Error("cannot write '" + *path + "': directory '" + parent.string() + "' does not exist");
      }
    }
    const RunOutcome run = run_sequence(req);
    if (!a->output.empty()) odometry::io::write_tum_trajectory(a->output, run.trajectory);
    if (!a->log.empty()) write_pair_log(a->log, run);
    std::cout << run_summary_line(run) << std::endl;
  });
}

}  // namespace bivo::experiments::cli
