#include "experiments/report_builder.h"

#include <unistd.h>

#include <chrono>
#include <ctime>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "experiments/pareto_study.h"
#include "experiments/plotting.h"
#include "experiments/tracker_config.h"
#include "odometry/io/atomic_file.h"
#include "odometry/io/tum_dataset.h"
#include "solvers/error.h"

namespace bivo::experiments {
namespace {

std::string now_utc() {
  const std::time_t t = std::time(nullptr);
  char buf[64];
  std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M UTC", std::gmtime(&t));
  return buf;
}

std::string setup_markdown(const ReportOptions& o, const MethodMatrix& m) {
  std::ostringstream s;
  s << "| setting | value |\n|---|---|\n";
  s << "| generated | " << now_utc() << " on " << ::sysconf(_SC_NPROCESSORS_ONLN) << " CPU core(s) |\n";
  s << "| sequences | " << m.sequences.size() << " |\n";
  s << "| frames per sequence | " << (o.max_frames < 0 ? std::string("all") : std::to_string(o.max_frames))
    << " from frame " << o.first_frame << " |\n";
  s << "| methods | ";
  for (size_t i = 0; i < m.methods.size(); ++i) {
    s << (i ? ", " : "") << label(m.methods[i]) << " [" << m.at(int(i), 0).backend << "]";
  }
  s << " |\n| pyramid | " << o.tracker.levels << " levels, finest " << o.tracker.finest_level
    << ", at most " << o.tracker.max_iterations << " iterations per level |\n";
  s << "| policy | fixed lambda " << o.tracker.policy.lambda << ", phi " << o.tracker.policy.phi << ", delta "
    << o.tracker.policy.delta << " m/px, eps_min " << o.tracker.policy.eps_min << ", eps_max "
    << o.tracker.policy.eps_max << " m^2 per unit weight |\n";
  s << "\n| sequence | frames processed | ground truth |\n|---|---:|---|\n";
  for (size_t c = 0; c < m.sequences.size(); ++c) {
    const auto& cell = m.at(0, int(c));
    s << "| " << m.sequences[c] << " | " << (cell.run ? std::to_string(cell.run->trajectory.size()) : "—") << " | "
      << (cell.run && cell.run->groundtruth ? "yes" : "no") << " |\n";
  }
  return s.str();
}

}  // namespace

ReportResult build_report(const ReportOptions& o, const std::string& dir) {
  namespace fs = std::filesystem;
  fs::create_directories(dir + "/images");
  ReportResult result;
  std::ostringstream md;
  md << "# " << o.title << "\n\n" << o.preamble << (o.preamble.empty() ? "" : "\n\n");

  // 1. Methods x sequences. Stages are announced on stderr: the runs can take minutes.
  std::cerr << "report: running " << o.methods.size() << " method(s) on " << o.sequences.size()
            << " sequence(s)...\n";
  MatrixOptions mo;
  mo.sequences = o.sequences;
  mo.methods = o.methods;
  mo.tracker = o.tracker;
  mo.first_frame = o.first_frame;
  mo.max_frames = o.max_frames;
  mo.progress = o.progress;
  mo.trajectory_dir = dir + "/trajectories";
  result.matrix = run_matrix(mo);
  result.tables_markdown = write_matrix(result.matrix, dir + "/tables");
  md << "## Setup\n\n" << setup_markdown(o, result.matrix) << "\n## Accuracy and runtime\n\n"
     << result.tables_markdown << "\n";

  auto image = [&](const std::string& script, const std::string& input, const std::string& name,
                   const std::string& caption) {
    if (!o.plots) return;
    const std::string png = dir + "/images/" + name;
    plot(script, {input, png});
    result.images.push_back(png);
    md << "![" << caption << "](images/" << name << ")\n\n*" << caption << "*\n\n";
  };

  md << "## Per-frame translational error (paper fig. 5)\n\n"
        "Error of each frame pair's estimated motion T_21 against the ground-truth motion, "
        "|translation of T_true^-1 T_est|.\n\n";
  image("per_frame_error.py", dir + "/tables/pairs.csv", "per_frame_error.png",
        "Per-frame translational error of every method, one panel per sequence");

  // 2. Sweeps.
  if (!o.lambdas.empty() || !o.epsilons.empty()) {
    SweepOptions so;
    for (size_t c = 0; c < o.sequences.size(); ++c) {
      const auto& cell = result.matrix.at(0, int(c));
      if (cell.run && cell.run->groundtruth) so.sequences.push_back(o.sequences[c]);
    }
    so.lambdas = o.lambdas;
    so.epsilons = o.epsilons;
    so.tracker = o.tracker;
    so.first_frame = o.first_frame;
    so.max_frames = o.sweep_max_frames;
    so.progress = o.progress;
    md << "## Error vs lambda and epsilon (paper fig. 3)\n\n"
       << "Method `fixed` over a log grid of lambda and method `bounded` with a fixed bound epsilon on F_D "
          "per unit weight, over the first "
       << o.sweep_max_frames
       << " frames of each sequence; ratios are to the single-objective run of the same frames (below 1: "
          "the depth objective helps).\n\n";
    std::cerr << "report: lambda/epsilon sweeps...\n";
    if (so.sequences.empty()) {
      md << "No sequence with ground truth: no sweep.\n\n";
    } else {
      const SweepResult sr = run_sweep(so);
      md << write_sweep(sr, dir + "/sweep") << "\n";
      if (!sr.points.empty()) {
        image("parameter_sweep.py", dir + "/sweep/sweep.csv", "sweep.png",
              "RPE RMSE and max-error ratios to the single-objective run vs lambda (left) and epsilon (right)");
      }
    }
  }

  // 3. Pareto fronts: the middle pair of each sequence's window.
  if (o.pareto) {
    md << "## Pareto fronts of one frame pair per sequence\n\n"
          "F_I and F_D of every point evaluated at its pose with robust weights estimated there; colour = "
          "translation error of the point's T_21 against ground truth; stars = the pose each method "
          "estimates for the pair; diamond = knee (farthest from the chord in normalized objectives).\n\n";
    fs::create_directories(dir + "/pareto");
    std::cerr << "report: Pareto fronts...\n";
    for (size_t c = 0; c < o.sequences.size(); ++c) {
      const auto& cell = result.matrix.at(0, int(c));
      if (!cell.run || cell.run->pairs.empty()) continue;
      ParetoStudyOptions po;
      po.sequence_dir = o.sequences[c];
      po.pair = cell.run->pairs[cell.run->pairs.size() / 2].index;
      po.level = o.pareto_level;
      po.points = o.pareto_points;
      po.tracker = o.tracker;
      po.methods.clear();
      for (const auto& m : o.methods) po.methods.push_back(m.method);
      try {
        const ParetoStudy s = run_pareto_study(po);
        const std::string json = dir + "/pareto/" + result.matrix.sequences[c] + ".json";
        odometry::io::write_file_atomically(json, [&](std::ostream& out) { out << pareto_json(s); });
        md << "### " << result.matrix.sequences[c] << ", pair " << s.pair << "\n\n";
        md << "| point | F_I | F_D | translation error [mm] |\n|---|---:|---:|---:|\n";
        auto row = [&](const std::string& name, const StudyPoint& p) {
          md << "| " << name << " | " << std::setprecision(6) << p.f_i << " | " << p.f_d << " | ";
          if (p.error) md << std::fixed << std::setprecision(2) << 1000.0 * p.error->translation_m << std::defaultfloat;
          else md << "—";
          md << " |\n";
        };
        for (const auto& p : s.methods) row(p.method, p);
        if (s.knee) row("knee", *s.knee);
        md << "\n";
        image("pareto_front.py", json, "pareto_" + result.matrix.sequences[c] + ".png",
              "Pareto front of " + result.matrix.sequences[c] + " pair " + std::to_string(s.pair));
      } catch (const Error& e) {
        md << "Pareto front of " << result.matrix.sequences[c] << " failed: " << e.what() << "\n\n";
      }
    }
  }

  md << "## Runtime (paper table 3)\n\n";
  image("runtime_bars.py", dir + "/tables/runtime_bars.csv", "runtime.png",
        "Time per frame pair, median over all pairs (bars) and mean (black mark), loading excluded");

  // The tracker settings every run of the report started from, for --config.
  write_tracker_config(dir + "/config.json", o.tracker);
  result.report_path = dir + "/report.md";
  odometry::io::write_file_atomically(result.report_path, [&](std::ostream& out) { out << md.str(); });
  return result;
}

}  // namespace bivo::experiments
