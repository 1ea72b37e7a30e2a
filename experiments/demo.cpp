// `bivo demo`'s engine (demo.h).
#include "experiments/demo.h"

#include <chrono>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "experiments/method_matrix.h"
#include "experiments/parameter_sweep.h"
#include "odometry/synth/sequence.h"

namespace bivo::experiments {

DemoResult run_demo(const DemoOptions& a) {
  namespace synth = odometry::synth;
  namespace fs = std::filesystem;
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - t0).count(); };

  ReportOptions o;
  o.title = "bivo demo: synthetic Structure vs. Texture (near)";
  o.tracker.levels = a.levels;
  o.tracker.finest_level = a.finest_level;
  for (const auto& m : a.methods) o.methods.push_back(parse_method_spec(m));
  if (a.sweep) {
    o.lambdas = log_grid(1e2, 1e6, 3);
    o.epsilons = log_grid(1e-4, 1e-2, 2);
    o.sweep_max_frames = a.sweep_frames;
  }
  const std::string seq_dir = a.output + "/sequences";
  {  // the options as the report will check them, before a minute of rendering
    MatrixOptions table;
    table.sequences = {seq_dir};
    table.methods = o.methods;
    table.tracker = o.tracker;
    check_matrix_options(table);
    if (a.sweep) {
      SweepOptions sweep;
      sweep.sequences = {seq_dir};
      sweep.tracker = o.tracker;
      sweep.lambdas = o.lambdas;
      sweep.max_frames = o.sweep_max_frames;
      sweep_units(sweep);
    }
  }
  std::vector<synth::SynthCategory> categories = synth::all_categories();
  categories.resize(4);  // the near ones, in the paper's column order
  for (const auto& c : categories) {
    synth::SynthOptions so;
    so.category = c;
    so.frames = a.frames;
    so.seed = a.seed;
    so.replace_own_folder = a.rerender;  // only a folder an earlier demo rendered
    const std::string path = seq_dir + "/" + synth::default_sequence_name(c);
    // A finished sequence folder only exists complete (rendered under a temporary name).
    if (a.rerender || !fs::exists(path + "/groundtruth.txt")) {
      std::cerr << "demo: rendering " << c.name() << " (" << a.frames << " frames)...\n";
      synth::render_sequence(so, seq_dir);
    } else {
      std::cerr << "demo: reusing " << path << "\n";
    }
    o.sequences.push_back(path);
  }
  const double render_s = elapsed();
  o.pareto = a.pareto;
  o.plots = a.plots;
  std::ostringstream pre;
  pre << "Four synthetic TUM-format sequences rendered by `bivo synth`'s renderer (the near categories of the "
         "paper's table 1: poor/rich structure x rich/poor texture; structure = zig-zag panels standing on a "
         "floor, both in view, texture = posters, no texture = white foil; camera 1.4 m from the scene), "
      << a.frames << " frames at 30 Hz each along generated hand-held motion (seed " << a.seed
      << "), Kinect-like depth and intensity noise; ground truth is exact. Motion is estimated coarse to fine "
         "down to pyramid level "
      << a.finest_level << " (" << (640 >> a.finest_level) << "x" << (480 >> a.finest_level)
      << "; `bivo demo --finest-level 0` for full resolution).";
  o.preamble = pre.str();
  DemoResult result;
  result.render_seconds = render_s;
  result.report = build_report(o, a.output);
  result.experiment_seconds = elapsed() - render_s;
  return result;
}

}  // namespace bivo::experiments
