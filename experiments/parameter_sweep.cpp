#include "experiments/parameter_sweep.h"

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include <nlohmann/json.hpp>

#include "experiments/result_table.h"
#include "experiments/sequence_runner.h"
#include "odometry/io/atomic_file.h"
#include "odometry/io/metrics.h"
#include "solvers/error.h"

namespace bivo::experiments {

std::vector<double> log_grid(double lo, double hi, int n) {
  if (!(lo > 0) || !(hi >= lo) || n < 1 || !std::isfinite(hi)) {
    std::ostringstream m;
    m << "log grid needs 0 < min <= max and at least 1 point (got min=" << lo << ", max=" << hi << ", points=" << n
      << ")";
    throw Error(m.str());
  }
  std::vector<double> v;
  for (int i = 0; i < n; ++i) {
    v.push_back(n == 1 ? lo : std::pow(10.0, std::log10(lo) + (std::log10(hi) - std::log10(lo)) * i / (n - 1)));
  }
  return v;
}

SweepResult run_sweep(const SweepOptions& o) {
  if (o.sequences.empty()) throw Error("sweep: no sequences given");
  if (o.lambdas.empty() && o.epsilons.empty()) throw Error("sweep: neither lambdas nor epsilons given");
  SweepResult out;
  for (const auto& dir : o.sequences) {
    RunRequest base;
    base.sequence_dir = dir;
    base.tracker = o.tracker;
    base.first_frame = o.first_frame;
    base.max_frames = o.max_frames;
    base.progress = o.progress;
    auto run_rpe = [&](RunRequest req, const std::string& what) {
      req.label = std::filesystem::path(dir).filename().string() + " " + what;
      RunOutcome run = run_sequence(req);
      if (!run.groundtruth) throw Error("sweep: sequence '" + dir + "' has no groundtruth.txt");
      return std::make_pair(odometry::io::relative_pose_error(*run.groundtruth, run.trajectory), run);
    };
    RunRequest single = base;
    single.tracker.method = "single";
    single.tracker.backend = "";
    const auto [ref, ref_run] = run_rpe(single, "single");
    if (!(ref.trans_rmse > 0) || !(ref.trans_max > 0)) {
      throw Error("sweep: the single-objective run on '" + dir + "' has zero error; ratios are undefined");
    }
    auto add = [&](const std::string& parameter, double value, RunRequest req) {
      std::ostringstream what;
      what << parameter << "=" << value;
      try {
        const auto [rpe, run] = run_rpe(req, what.str());
        SweepPoint p;
        p.sequence = ref_run.sequence.rfind("rgbd_dataset_", 0) == 0 ? ref_run.sequence.substr(13) : ref_run.sequence;
        p.parameter = parameter;
        p.value = value;
        p.rpe_trans = rpe.trans_rmse;
        p.max_err = rpe.trans_max;
        p.rmse_ratio = rpe.trans_rmse / ref.trans_rmse;
        p.max_ratio = rpe.trans_max / ref.trans_max;
        p.median_ms = run.median_ms;
        p.failures = run.failures;
        out.points.push_back(p);
      } catch (const Error& e) {
        out.notes.push_back(ref_run.sequence + " " + what.str() + ": " + e.what());
      }
    };
    for (double lambda : o.lambdas) {
      RunRequest req = base;
      req.tracker.method = "fixed";
      req.tracker.backend = "";
      req.tracker.policy.lambda = lambda;
      add("lambda", lambda, req);
    }
    for (double eps : o.epsilons) {
      RunRequest req = base;
      req.tracker.method = "bounded";
      req.tracker.backend = o.epsilon_backend;
      req.tracker.policy.eps = eps;
      add("epsilon", eps, req);
    }
  }
  return out;
}

std::string write_sweep(const SweepResult& r, const std::string& dir) {
  std::filesystem::create_directories(dir);
  std::ostringstream csv, md;
  csv << "sequence,parameter,value,rpe_trans,max_err,rmse_ratio,max_ratio,median_ms,failures\n";
  md << "| sequence | parameter | value | RPE trans [m/s] | max [m/s] | RMSE ratio | max ratio | ms/pair |\n"
        "|---|---|---:|---:|---:|---:|---:|---:|\n";
  nlohmann::json j = nlohmann::json::array();
  for (const auto& p : r.points) {
    csv << csv_field(p.sequence) << "," << p.parameter << "," << std::setprecision(10) << p.value << ","
        << p.rpe_trans << "," << p.max_err << "," << p.rmse_ratio << "," << p.max_ratio << "," << p.median_ms << ","
        << p.failures << "\n";
    md << "| " << p.sequence << " | " << p.parameter << " | " << std::setprecision(4) << p.value << " | "
       << std::fixed << std::setprecision(6) << p.rpe_trans << " | " << p.max_err << " | " << std::setprecision(3)
       << p.rmse_ratio << " | " << p.max_ratio << " | " << std::setprecision(1) << p.median_ms << " |\n"
       << std::defaultfloat;
    j.push_back({{"sequence", p.sequence}, {"parameter", p.parameter}, {"value", p.value},
                 {"rpe_trans", p.rpe_trans}, {"max_err", p.max_err}, {"rmse_ratio", p.rmse_ratio},
                 {"max_ratio", p.max_ratio}, {"median_ms", p.median_ms}, {"failures", p.failures}});
  }
  if (!r.notes.empty()) {
    md << "\nLeft out:\n\n";
    for (const auto& n : r.notes) md << "- " << n << "\n";
  }
  odometry::io::write_file_atomically(dir + "/sweep.csv", [&](std::ostream& o) { o << csv.str(); });
  odometry::io::write_file_atomically(dir + "/sweep.json", [&](std::ostream& o) {
    o << nlohmann::json{{"points", j}, {"notes", r.notes}}.dump(2) << "\n";
  });
  odometry::io::write_file_atomically(dir + "/sweep.md", [&](std::ostream& o) { o << md.str(); });
  return md.str();
}

}  // namespace bivo::experiments
