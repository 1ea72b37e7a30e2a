#include "experiments/report_builder.h"

#include <unistd.h>

#include <chrono>
#include <ctime>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "experiments/paper_claims.h"
#include "experiments/plotting.h"
#include "experiments/study/study_merge.h"
#include "experiments/study/study_plan.h"
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
  s << " |\n| pyramid | " << o.tracker.levels << " levels, finest " << o.tracker.finest_level << ", at most "
    << o.tracker.max_iterations << " iterations per level |\n";
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

ReportResult write_report(const ReportOptions& o, const ReportParts& parts, const std::string& dir) {
  namespace fs = std::filesystem;
  odometry::io::create_output_directory(dir + "/images");
  ReportResult result;
  std::ostringstream md;
  md << "# " << o.title << "\n\n" << o.preamble << (o.preamble.empty() ? "" : "\n\n");

  // 1. Methods x sequences.
  result.matrix = parts.matrix;
  write_matrix_trajectories(result.matrix, dir + "/trajectories");
  result.tables_markdown = write_matrix(result.matrix, dir + "/tables");
  md << "## Setup\n\n"
     << setup_markdown(o, result.matrix) << "\n## Accuracy and runtime\n\n"
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
    md << "## Error vs lambda and epsilon (paper fig. 3)\n\n"
       << "Method `fixed` over a log grid of lambda and method `bounded` with a fixed bound epsilon on F_D "
          "per unit weight, over the first "
       << o.sweep_max_frames
       << " frames of each sequence; ratios are to the single-objective run of the same frames (below 1: "
          "the depth objective helps).\n\n";
    if (!parts.sweep) {
      md << "No sequence with ground truth: no sweep.\n\n";
    } else {
      md << write_sweep(*parts.sweep, dir + "/sweep") << "\n";
      if (!parts.sweep->points.empty()) {
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
    odometry::io::create_output_directory(dir + "/pareto");
    for (const ReportPareto& rp : parts.pareto) {
      if (!rp.study) {
        md << "Pareto front of " << rp.sequence << " failed: " << rp.error << "\n\n";
        continue;
      }
      const ParetoStudy& s = *rp.study;
      const std::string json = dir + "/pareto/" + rp.sequence + ".json";
      odometry::io::write_file_atomically(json, [&](std::ostream& out) { out << pareto_json(s); });
      md << "### " << rp.sequence << ", pair " << s.pair << "\n\n";
      md << "| point | F_I | F_D | translation error [mm] |\n|---|---:|---:|---:|\n";
      auto row = [&](const std::string& name, const StudyPoint& p) {
        md << "| " << name << " | " << std::setprecision(6) << p.f_i << " | " << p.f_d << " | ";
        if (p.error)
          md << std::fixed << std::setprecision(2) << 1000.0 * p.error->translation_m << std::defaultfloat;
        else
          md << "—";
        md << " |\n";
      };
      for (const auto& p : s.methods) row(p.method, p);
      if (s.knee) row("knee", *s.knee);
      md << "\n";
      image("pareto_front.py", json, "pareto_" + rp.sequence + ".png",
            "Pareto front of " + rp.sequence + " pair " + std::to_string(s.pair));
    }
  }

  md << "## Runtime (paper table 3)\n\n";
  image("runtime_bars.py", dir + "/tables/runtime_bars.csv", "runtime.png",
        "Time per frame pair, median over all pairs (bars) and mean (black mark), loading excluded");

  md << "## The paper's claims, one by one\n\n"
     << claims_markdown(paper_claims(result.matrix, parts.sweep ? &*parts.sweep : nullptr)) << "\n";

  // The tracker settings every run of the report started from, for --config.
  write_tracker_config(dir + "/config.json", o.tracker);
  result.report_path = dir + "/report.md";
  odometry::io::write_file_atomically(result.report_path, [&](std::ostream& out) { out << md.str(); });
  return result;
}

ReportResult build_report(const ReportOptions& o, const std::string& dir) {
  return *run_study(report_study(o, dir), &std::cerr).report;
}

}  // namespace bivo::experiments
