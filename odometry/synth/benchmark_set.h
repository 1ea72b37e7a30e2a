#pragma once
// The synthetic benchmark set: one fixed definition of the eight "Structure vs. Texture"
// categories (structure/nostructure x texture/notexture x near/far), 300 frames each along
// real fr3 camera motion, with fixed seeds, so everyone renders byte-identical sequences
// (`bivo synth --benchmark-set`, docs/synthetic.md "Benchmark set").
//
// Usage:
//   namespace synth = bivo::odometry::synth;
//   for (const synth::BenchmarkSequence& b : synth::benchmark_set()) { ... b.category ... }
//   std::vector<std::string> dirs =
//       synth::render_benchmark_set("../shared/data/trajectories", "/work/benchset");
//   // dirs[k] == "/work/benchset/rgbd_dataset_freiburg3_synth_<category>"; the folder also
//   // gets benchmark_set.json (the definition and a digest of every sequence's files).
#include <cstdint>
#include <string>
#include <vector>

#include "odometry/synth/scene.h"
#include "odometry/synth/sequence.h"

namespace bivo::odometry::synth {

inline constexpr int kBenchmarkFrames = 300;
inline constexpr std::uint64_t kBenchmarkSeed = 1;

struct BenchmarkSequence {
  SynthCategory category;
  // Ground-truth file (TUM "<sequence>-groundtruth.txt") in the trajectories folder.
  std::string trajectory;
  double start_offset_s = 0.0;  // frames start this long after its first pose
  std::string motion_choice;    // why this motion (the fr3 twin's, or the documented choice)
};

// The eight sequences in the paper's table order (near first, all_categories()).
std::vector<BenchmarkSequence> benchmark_set();

// The entry of `category` ("structure_texture_near", ...); throws bivo::Error naming it.
BenchmarkSequence benchmark_sequence(const std::string& category);

// Options bivo synth renders an entry with: kBenchmarkFrames, kBenchmarkSeed, default
// sensor and scene, the default sequence name; `threads` does not change the bytes.
SynthOptions benchmark_options(const BenchmarkSequence& entry, int threads = 0);

// Renders the entries (all, or only `category` when not empty) from the trajectories in
// `trajectories_dir` into output_dir/<sequence name>, then writes output_dir/
// benchmark_set.json. Returns the sequence folders. Throws bivo::Error naming a missing
// trajectory file or an existing sequence folder before anything is rendered
// (`replace_own_folder`: see SynthOptions).
std::vector<std::string> render_benchmark_set(const std::string& trajectories_dir, const std::string& output_dir,
                                              const std::string& category = "", int threads = 0,
                                              bool replace_own_folder = false);

// 64-bit FNV-1a digest (16 hex digits) of a sequence folder: every regular file's relative
// path and bytes, in sorted path order. Equal digests = byte-identical renderings.
std::string sequence_digest(const std::string& directory);

}  // namespace bivo::odometry::synth
