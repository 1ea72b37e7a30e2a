#include "odometry/synth/benchmark_set.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "odometry/io/atomic_file.h"
#include "odometry/io/staged_folder.h"
#include "odometry/io/trajectory.h"
#include "solvers/error.h"

namespace bivo::odometry::synth {

namespace fs = std::filesystem;

namespace {

constexpr const char* kStructureNear = "rgbd_dataset_freiburg3_structure_texture_near-groundtruth.txt";
constexpr const char* kStructureFar = "rgbd_dataset_freiburg3_structure_texture_far-groundtruth.txt";
constexpr const char* kNostructureNear = "rgbd_dataset_freiburg3_nostructure_texture_near_withloop-groundtruth.txt";

// Which real fr3 motion drives a category: its own fr3 sequence where one is at hand, else
// the recording of the same scene type and distance, so that a texture/notexture pair
// shares scene, motion, noise and depth images (only the albedo differs).
BenchmarkSequence entry_for(const SynthCategory& c) {
  BenchmarkSequence b;
  b.category = c;
  b.start_offset_s = 0.0;  // the first 10 s of each recording
  if (c.structure) {
    b.trajectory = c.near ? kStructureNear : kStructureFar;
    b.motion_choice = c.texture ? "its fr3 twin's motion"
                                : "the motion of its texture twin (fr3 structure_texture_" +
                                      std::string(c.near ? "near" : "far") + ")";
  } else if (c.near) {
    b.trajectory = kNostructureNear;
    b.motion_choice = c.texture ? "its fr3 twin's motion (fr3 nostructure_texture_near_withloop)"
                                : "the motion of its texture twin (fr3 nostructure_texture_near_withloop)";
  } else {
    b.trajectory = kStructureFar;
    b.motion_choice =
        "no fr3 far planar trajectory is at hand: the only real far-distance recording "
        "(fr3 structure_texture_far), the same motion as the structure_*_far pair";
  }
  return b;
}

std::string hex64(std::uint64_t v) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

}  // namespace

std::vector<BenchmarkSequence> benchmark_set() {
  std::vector<BenchmarkSequence> out;
  for (const SynthCategory& c : all_categories()) out.push_back(entry_for(c));
  return out;
}

BenchmarkSequence benchmark_sequence(const std::string& category) { return entry_for(parse_category(category)); }

SynthOptions benchmark_options(const BenchmarkSequence& entry, int threads) {
  SynthOptions o;
  o.category = entry.category;
  o.frames = kBenchmarkFrames;
  o.seed = kBenchmarkSeed;
  o.start_offset_s = entry.start_offset_s;
  o.threads = threads;
  return o;
}

std::vector<std::string> render_benchmark_set(const std::string& trajectories_dir, const std::string& output_dir,
                                              const std::string& category, int threads, bool replace_own_folder) {
  std::vector<BenchmarkSequence> entries;
  if (category.empty())
    entries = benchmark_set();
  else
    entries.push_back(benchmark_sequence(category));
  std::vector<io::Trajectory> motions;
  for (const BenchmarkSequence& b : entries) {
    const fs::path p = fs::path(trajectories_dir) / b.trajectory;
    if (!fs::is_regular_file(p)) {
      throw Error("benchmark set: trajectory '" + p.string() + "' (for " + b.category.name() +
                  ") not found; pass the folder holding the TUM *-groundtruth.txt files");
    }
    motions.push_back(io::read_tum_trajectory(p.string()));
  }
  std::vector<SynthOptions> options;
  for (const BenchmarkSequence& b : entries) {
    options.push_back(benchmark_options(b, threads));
    options.back().replace_own_folder = replace_own_folder;
    io::check_folder_target((fs::path(output_dir) / default_sequence_name(b.category)).string(), replace_own_folder);
  }
  std::vector<std::string> dirs;
  nlohmann::json sequences = nlohmann::json::array();
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const BenchmarkSequence& b = entries[k];
    // The motion is named by its file name only: the bytes do not depend on where the data lives.
    dirs.push_back(render_sequence(options[k], motions[k], output_dir, b.trajectory));
    sequences.push_back({{"category", b.category.name()},
                         {"folder", fs::path(dirs.back()).filename().string()},
                         {"trajectory", b.trajectory},
                         {"start_offset_s", b.start_offset_s},
                         {"motion_choice", b.motion_choice},
                         {"digest_fnv1a64", sequence_digest(dirs.back())}});
  }
  const nlohmann::json manifest{{"generator", "bivo synth --benchmark-set"},
                                {"frames", kBenchmarkFrames},
                                {"seed", kBenchmarkSeed},
                                {"sequences", sequences}};
  // Rendering one category leaves the manifest of a full set alone.
  const std::string name = category.empty() ? "benchmark_set.json" : "benchmark_set." + category + ".json";
  io::write_file_atomically((fs::path(output_dir) / name).string(),
                            [&](std::ostream& out) { out << manifest.dump(2) << "\n"; });
  return dirs;
}

std::string sequence_digest(const std::string& directory) {
  std::vector<fs::path> files;
  for (const auto& e : fs::recursive_directory_iterator(directory)) {
    // The ".bivo-" bookkeeping files (the output marker) are not part of the rendering.
    if (e.is_regular_file() && e.path().filename().string().rfind(".bivo-", 0) != 0) {
      files.push_back(fs::relative(e.path(), directory));
    }
  }
  std::sort(files.begin(), files.end());
  std::uint64_t h = 0xcbf29ce484222325ull;
  const auto feed = [&h](const char* data, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) {
      h ^= static_cast<unsigned char>(data[i]);
      h *= 0x100000001b3ull;
    }
  };
  std::vector<char> buf(1 << 16);
  for (const fs::path& rel : files) {
    const std::string name = rel.generic_string();
    // Name, its terminating 0 and the size in bytes first: files cannot run together.
    const std::uint64_t size = fs::file_size(fs::path(directory) / rel);
    feed(name.c_str(), name.size() + 1);
    feed(reinterpret_cast<const char*>(&size), sizeof size);
    std::ifstream in(fs::path(directory) / rel, std::ios::binary);
    if (!in) throw Error("sequence digest: cannot read '" + (fs::path(directory) / rel).string() + "'");
    while (in.read(buf.data(), buf.size()) || in.gcount() > 0) feed(buf.data(), static_cast<std::size_t>(in.gcount()));
  }
  return hex64(h);
}

}  // namespace bivo::odometry::synth
