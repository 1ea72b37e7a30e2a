// `bivo depth-stats SEQ...`: statistics of each sequence's depth residual at the ground-truth
// motion (experiments/depth_residual_stats.h), one table row per sequence, so renderings
// can be compared with real recordings.
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "experiments/cli/commands.h"
#include "experiments/depth_residual_stats.h"

namespace bivo::experiments::cli {

void add_depth_stats_command(CLI::App& app) {
  struct Args {
    std::vector<std::string> sequences;
    DepthResidualOptions options;
  };
  auto a = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "depth-stats", "Depth residual at the true motion (mean, spread, correlation, radial and depth dependence)");
  cmd->add_option("sequences", a->sequences, "TUM sequence folders with groundtruth.txt")->required();
  cmd->add_option("--gap", a->options.gap, "frames between the two images of a pair")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000000));
  cmd->add_option("--pairs", a->options.max_pairs, "pairs spread evenly over each sequence")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000000));
  cmd->add_option("--max-frames", a->options.max_frames, "only the first N frames (-1: all)")->capture_default_str();
  cmd->callback([a] {
    std::vector<DepthResidualStats> rows;
    for (const std::string& s : a->sequences) rows.push_back(depth_residual_stats(s, a->options));
    std::cout << depth_residual_table(rows);
  });
}

}  // namespace bivo::experiments::cli
