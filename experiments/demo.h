#pragma once
// The README's main job (`bivo demo`): renders the built-in synthetic "Structure vs.
// Texture" set (the four near categories, generated hand-held motion; no data needed), runs
// the paper's methods and the data-driven joint, noise-bounded and robust on it and writes
// a report folder (report_builder.h).
#include <cstdint>
#include <string>
#include <vector>

#include "experiments/report_builder.h"

namespace bivo::experiments {

struct DemoOptions {
  std::string output = "demo-output";  // report folder; sequences go to OUTPUT/sequences
  int frames = 90, levels = 4;
  // Level 1 (320x240) by default keeps the demo within minutes on two cores; 0 solves at
  // full resolution like `bivo run`.
  int finest_level = 1;
  std::uint64_t seed = 7;
  std::vector<std::string> methods{"single",  "depth", "tykkala",       "weighted",
                                   "bounded", "joint", "noise-bounded", "robust"};
  int sweep_frames = 40;
  bool sweep = true, pareto = true, plots = true;
  bool rerender = false;  // render even when OUTPUT/sequences has a finished sequence
};

struct DemoResult {
  ReportResult report;
  double render_seconds = 0, experiment_seconds = 0;
};

DemoResult run_demo(const DemoOptions& options);

}  // namespace bivo::experiments
