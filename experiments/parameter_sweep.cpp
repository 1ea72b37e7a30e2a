#include "experiments/parameter_sweep.h"

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include <nlohmann/json.hpp>

#include "experiments/method_matrix.h"
#include "experiments/result_table.h"
#include "experiments/sequence_runner.h"
#include "experiments/trajectory_evaluation.h"
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

std::vector<SweepUnit> sweep_units(const SweepOptions& o) {
  if (o.sequences.empty()) throw Error("sweep: no sequences given");
  if (o.lambdas.empty() && o.epsilons.empty()) throw Error("sweep: neither lambdas nor epsilons given");
  odometry::TrackerOptions window = with_frame_window(o.tracker, o.first_frame, o.max_frames);
  window.method = "single";  // each unit's method is its own; the window is checked once
  window.backend = "";
  odometry::validate(window);
  std::vector<SweepUnit> units;
  for (int s = 0; s < int(o.sequences.size()); ++s) {
    units.push_back({s, "single", 0.0});
    for (double lambda : o.lambdas) units.push_back({s, "lambda", lambda});
    for (double eps : o.epsilons) units.push_back({s, "epsilon", eps});
  }
  return units;
}

namespace {

std::string point_name(const SweepUnit& u) {
  std::ostringstream what;
  if (u.parameter == "single")
    what << "single";
  else
    what << u.parameter << "=" << u.value;
  return what.str();
}

}  // namespace

SweepRun run_sweep_unit(const SweepOptions& o, const SweepUnit& unit) {
  const std::string& dir = o.sequences.at(unit.sequence);
  RunRequest req;
  req.sequence_dir = dir;
  req.tracker = o.tracker;
  req.first_frame = o.first_frame;
  req.max_frames = o.max_frames;
  req.progress = o.progress;
  req.label = std::filesystem::path(dir).filename().string() + " " + point_name(unit);
  req.tracker.backend = "";
  if (unit.parameter == "single") {
    req.tracker.method = "single";
  } else if (unit.parameter == "lambda") {
    req.tracker.method = "fixed";
    req.tracker.policy.lambda = unit.value;
  } else if (unit.parameter == "epsilon") {
    req.tracker.method = "bounded";
    req.tracker.backend = o.epsilon_backend;
    req.tracker.policy.eps = unit.value;
  } else {
    throw Error("sweep: unknown parameter '" + unit.parameter + "'");
  }
  SweepRun out;
  out.unit = unit;
  out.sequence = sequence_labels(o.sequences).at(unit.sequence);  // distinct even for same-named folders
  try {
    const RunOutcome run = run_sequence(req);
    if (!run.groundtruth) throw Error("sweep: sequence '" + dir + "' has no groundtruth.txt");
    std::string why;
    const auto rpe = rpe_if_long_enough(*run.groundtruth, run.trajectory, o.rpe_delta, why);
    if (!rpe) throw Error(why);
    out.rpe_trans = rpe->trans_rmse;
    out.max_err = rpe->trans_max;
    out.median_ms = run.median_ms;
    out.failures = run.failures;
    out.ok = true;
  } catch (const Error& e) {
    out.error = e.what();
  }
  return out;
}

SweepResult assemble_sweep(const SweepOptions& o, const std::vector<SweepRun>& runs) {
  const std::vector<SweepUnit> units = sweep_units(o);
  if (runs.size() != units.size()) {
    throw Error("sweep: " + std::to_string(runs.size()) + " runs for " + std::to_string(units.size()) + " units");
  }
  SweepResult out;
  out.rpe_delta = o.rpe_delta;
  const SweepRun* ref = nullptr;
  for (const SweepRun& r : runs) {
    if (r.unit.parameter == "single") {
      ref = &r;
      if (r.missing) {
        out.notes.push_back(r.sequence + ": the single-objective reference was not run; its points are left out");
      } else if (!r.ok) {
        out.notes.push_back(r.sequence + ": the single-objective reference failed (" + r.error +
                            "); its points are left out");
      } else if (!(r.rpe_trans > 0) || !(r.max_err > 0)) {
        out.notes.push_back(r.sequence +
                            ": the single-objective reference has zero error; ratios are undefined, "
                            "its points are left out");
      }
      continue;
    }
    if (!ref || ref->missing || !ref->ok || !(ref->rpe_trans > 0) || !(ref->max_err > 0)) continue;
    if (r.missing) {
      out.notes.push_back(ref->sequence + " " + point_name(r.unit) + ": not run");
      continue;
    }
    if (!r.ok) {
      out.notes.push_back(ref->sequence + " " + point_name(r.unit) + ": " + r.error);
      continue;
    }
    SweepPoint p;
    p.sequence = ref->sequence.rfind("rgbd_dataset_", 0) == 0 ? ref->sequence.substr(13) : ref->sequence;
    p.parameter = r.unit.parameter;
    p.value = r.unit.value;
    p.rpe_trans = r.rpe_trans;
    p.max_err = r.max_err;
    p.rmse_ratio = r.rpe_trans / ref->rpe_trans;
    p.max_ratio = r.max_err / ref->max_err;
    p.median_ms = r.median_ms;
    p.failures = r.failures;
    out.points.push_back(p);
  }
  return out;
}

SweepResult run_sweep(const SweepOptions& o) {
  std::vector<SweepRun> runs;
  for (const SweepUnit& u : sweep_units(o)) runs.push_back(run_sweep_unit(o, u));
  return assemble_sweep(o, runs);
}

std::string write_sweep(const SweepResult& r, const std::string& dir) {
  odometry::io::create_output_directory(dir);
  std::ostringstream csv, md;
  csv << "sequence,parameter,value,rpe_trans,max_err,rmse_ratio,max_ratio,median_ms,failures\n";
  const std::string unit = rpe_unit("m", r.rpe_delta);
  md << "| sequence | parameter | value | RPE trans [" << unit << "] | max [" << unit
     << "] | RMSE ratio | max ratio | ms/pair |\n"
        "|---|---|---:|---:|---:|---:|---:|---:|\n";
  nlohmann::json j = nlohmann::json::array();
  for (const auto& p : r.points) {
    csv << csv_field(p.sequence) << "," << p.parameter << "," << std::setprecision(10) << p.value << "," << p.rpe_trans
        << "," << p.max_err << "," << p.rmse_ratio << "," << p.max_ratio << "," << p.median_ms << "," << p.failures
        << "\n";
    md << "| " << p.sequence << " | " << p.parameter << " | " << std::setprecision(4) << p.value << " | " << std::fixed
       << std::setprecision(6) << p.rpe_trans << " | " << p.max_err << " | " << std::setprecision(3) << p.rmse_ratio
       << " | " << p.max_ratio << " | " << std::setprecision(1) << p.median_ms << " |\n"
       << std::defaultfloat;
    j.push_back({{"sequence", p.sequence},
                 {"parameter", p.parameter},
                 {"value", p.value},
                 {"rpe_trans", p.rpe_trans},
                 {"max_err", p.max_err},
                 {"rmse_ratio", p.rmse_ratio},
                 {"max_ratio", p.max_ratio},
                 {"median_ms", p.median_ms},
                 {"failures", p.failures}});
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
