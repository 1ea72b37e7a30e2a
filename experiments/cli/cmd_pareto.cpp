// `bivo pareto SEQUENCE_DIR (--pair K | --every K) --output DIR`: Pareto fronts (F_I, F_D) of
// frame pairs by lambda and epsilon sweeps, with the methods' picks, the knee and pose errors
// (experiments/pareto_study.h); JSON per pair plus a PNG per pair and a Markdown summary.
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

#include "experiments/cli/commands.h"
#include "experiments/pareto_study.h"
#include "experiments/plotting.h"
#include "odometry/io/atomic_file.h"
#include "odometry/io/tum_dataset.h"
#include "solvers/error.h"

namespace bivo::experiments::cli {

void add_pareto_command(CLI::App& app) {
  struct Args {
    ParetoStudyOptions o;
    int pair = -1, every = -1, max_pairs = 5, levels = 4;
    std::string output;
    bool no_plots = false;
  };
  auto a = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("pareto", "Pareto fronts (F_I, F_D) of frame pairs by lambda and epsilon sweeps");
  cmd->add_option("sequence", a->o.sequence_dir, "TUM sequence folder")->required();
  auto* pair_opt = cmd->add_option("--pair", a->pair, "one pair: reference frame K, current K+1");
  auto* every_opt = cmd->add_option("--every", a->every, "every K-th pair (0, K, 2K, ...)");
  pair_opt->excludes(every_opt);
  cmd->add_option("--max-pairs", a->max_pairs, "with --every: at most this many pairs")->capture_default_str();
  cmd->add_option("--level", a->o.level, "pyramid level of the problem (0 = full resolution)")->capture_default_str();
  cmd->add_option("--levels", a->levels, "pyramid levels for the coarse-to-fine start")->capture_default_str();
  cmd->add_option("--points", a->o.points, "points per sweep")->capture_default_str();
  cmd->add_option("--lambda-min", a->o.lambda_min, "smallest lambda of the sweep")->capture_default_str();
  cmd->add_option("--lambda-max", a->o.lambda_max, "largest lambda of the sweep")->capture_default_str();
  cmd->add_option("--methods", a->o.methods, "methods whose picks are marked")->capture_default_str();
  cmd->add_option("--output", a->output, "folder for pareto_pair<K>.json/.png and pareto.md")->required();
  cmd->add_flag("--no-plots", a->no_plots, "write the JSON only (no matplotlib)");
  cmd->callback([a] {
    if (a->pair < 0 && a->every <= 0) throw Error("give --pair K (K >= 0) or --every K (K >= 1)");
    std::vector<int> pairs;
    if (a->pair >= 0) {
      pairs.push_back(a->pair);
    } else {
      const int frames = int(odometry::io::open_tum_sequence(a->o.sequence_dir).frames.size());
      for (int k = 0; k + 1 < frames && int(pairs.size()) < a->max_pairs; k += a->every) pairs.push_back(k);
    }
    std::filesystem::create_directories(a->output);
    std::ostringstream md;
    md << "| pair | level | lambda-front points | epsilon-front points | knee F_I | knee F_D | knee error [mm] |";
    for (const auto& m : a->o.methods) md << " " << m << " error [mm] |";
    md << " seconds |\n|---|---:|---:|---:|---:|---:|---:|";
    for (size_t i = 0; i < a->o.methods.size(); ++i) md << "---:|";
    md << "---:|\n";
    auto mm = [](const StudyPoint& p) {
      std::ostringstream s;
      if (p.error) s << std::fixed << std::setprecision(2) << 1000.0 * p.error->translation_m;
      else s << "—";
      return s.str();
    };
    for (int k : pairs) {
      ParetoStudyOptions o = a->o;
      o.pair = k;
      o.tracker.levels = a->levels;
      const ParetoStudy s = run_pareto_study(o);
      const std::string base = a->output + "/pareto_pair" + std::to_string(k);
      odometry::io::write_file_atomically(base + ".json", [&](std::ostream& out) { out << pareto_json(s); });
      if (!a->no_plots) plot("pareto_front.py", {base + ".json", base + ".png"});
      md << "| " << k << " | " << s.level << " | " << s.lambda_front.size() << " | " << s.epsilon_front.size() << " | ";
      if (s.knee) md << std::setprecision(6) << s.knee->f_i << " | " << s.knee->f_d << " | " << mm(*s.knee) << " |";
      else md << "— | — | — |";
      for (const auto& p : s.methods) md << " " << mm(p) << " |";
      md << " " << std::fixed << std::setprecision(1) << s.seconds << std::defaultfloat << " |\n";
      std::cerr << "pareto: pair " << k << " done in " << s.seconds << " s\n";
    }
    odometry::io::write_file_atomically(a->output + "/pareto.md", [&](std::ostream& out) { out << md.str(); });
    std::cout << md.str();
  });
}

}  // namespace bivo::experiments::cli
