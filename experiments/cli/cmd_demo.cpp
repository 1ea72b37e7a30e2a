// `bivo demo [--output DIR]`: the README's main job (experiments/demo.h): renders the
// built-in synthetic set, runs the paper's methods and joint, noise-bounded and robust on
// it, prints the RPE and runtime tables and writes a report folder.
#include <iomanip>
#include <iostream>
#include <memory>

#include "experiments/cli/commands.h"
#include "experiments/demo.h"
#include "experiments/output_set.h"

namespace bivo::experiments::cli {

void add_demo_command(CLI::App& app) {
  struct Args {
    DemoOptions o;
    bool no_sweep = false, no_pareto = false, no_plots = false;
  };
  auto a = std::make_shared<Args>();
  auto& o = a->o;
  auto* cmd = app.add_subcommand("demo",
                                 "Render the built-in synthetic set, run the paper's methods and the data-driven ones, "
                                 "print the tables, write a report");
  cmd->add_option("--output", o.output, "report folder (sequences are rendered into OUTPUT/sequences)")
      ->capture_default_str();
  cmd->add_option("--frames", o.frames, "frames per synthetic sequence")->capture_default_str();
  cmd->add_option("--seed", o.seed, "seed of textures, noise and hand-held motion")->capture_default_str();
  cmd->add_option("--methods", o.methods, "methods ('method' or 'method:backend')")->capture_default_str();
  cmd->add_option("--levels", o.levels, "pyramid levels")->capture_default_str();
  cmd->add_option("--finest-level", o.finest_level, "finest pyramid level solved (0 = 640x480, 1 = 320x240)")
      ->capture_default_str();
  cmd->add_option("--sweep-frames", o.sweep_frames, "frames per lambda/epsilon sweep run")->capture_default_str();
  cmd->add_flag("--no-sweep", a->no_sweep, "skip the lambda/epsilon sweeps");
  cmd->add_flag("--no-pareto", a->no_pareto, "skip the Pareto fronts");
  cmd->add_flag("--no-plots", a->no_plots, "tables only (no matplotlib)");
  cmd->add_flag("--rerender", o.rerender, "render the sequences even when OUTPUT/sequences has them");
  cmd->callback([a] {
    check_output_folder({"--output", a->o.output});
    DemoOptions o = a->o;
    o.sweep = !a->no_sweep;
    o.pareto = !a->no_pareto;
    o.plots = !a->no_plots;
    const DemoResult r = run_demo(o);
    std::cout << r.report.tables_markdown << std::fixed << std::setprecision(1) << "\nreport: " << r.report.report_path
              << "\ndemo: rendering " << r.render_seconds << " s, experiments " << r.experiment_seconds << " s\n";
  });
}

}  // namespace bivo::experiments::cli
