// Seed corpora for the fuzz targets, made by the project itself: a small rendered sequence
// (its lists and ground truth, crops of its frames as PNGs), generated hand-held motion and
// the conic problems of docs/conic.md's format.
#include <filesystem>
#include <fstream>
#include <sstream>

#include "harnesses.h"
#include "odometry/io/png_io.h"
#include "odometry/io/trajectory.h"
#include "odometry/synth/motion.h"
#include "odometry/synth/sequence.h"

namespace bivo::fuzz {
namespace {

namespace fs = std::filesystem;

void copy_into(const fs::path& from, const fs::path& dir, const std::string& name) {
  fs::copy_file(from, dir / name, fs::copy_options::overwrite_existing);
}

void write_text(const fs::path& file, const std::string& text) { std::ofstream(file) << text; }

}  // namespace

void write_seeds(const std::string& dir) {
  const fs::path root(dir);
  for (const auto& h : harnesses()) fs::create_directories(root / h.name);
  const fs::path scratch = root / "sequence";
  odometry::synth::SynthOptions o;
  o.category = odometry::synth::parse_category("structure_texture_near");
  o.frames = 3;
  o.threads = 1;
  const fs::path seq = odometry::synth::render_sequence(o, scratch.string());

  for (const char* list : {"rgb.txt", "depth.txt", "associations.txt"}) copy_into(seq / list, root / "tum_list", list);
  copy_into(seq / "groundtruth.txt", root / "trajectory", "groundtruth.txt");
  odometry::synth::HandheldMotionOptions h;
  h.duration_s = 0.3;
  odometry::io::write_tum_trajectory((root / "trajectory" / "handheld.txt").string(),
                                     odometry::synth::generate_handheld_motion(h));

  // 12 x 9 crops of the first frame: colour, gray and depth.
  std::ifstream rgb_list(seq / "associations.txt");
  std::string line, t_rgb, rgb_file, t_depth, depth_file;
  while (std::getline(rgb_list, line) && (line.empty() || line[0] == '#')) {
  }
  std::istringstream(line) >> t_rgb >> rgb_file >> t_depth >> depth_file;
  const odometry::io::Png8 rgb = odometry::io::read_png8((seq / rgb_file).string());
  const odometry::io::Png16 depth = odometry::io::read_png16((seq / depth_file).string());
  const int w = 12, h9 = 9, x0 = rgb.width / 2, y0 = rgb.height / 2;
  odometry::io::Png8 crop{w, h9, 3, {}}, gray{w, h9, 1, {}};
  odometry::io::Png16 dcrop{w, h9, {}};
  for (int y = y0; y < y0 + h9; ++y) {
    for (int x = x0; x < x0 + w; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * rgb.width + x;
      for (int c = 0; c < 3; ++c) crop.data.push_back(rgb.data[3 * i + c]);
      gray.data.push_back(rgb.data[3 * i + 1]);
      dcrop.data.push_back(depth.data[i]);
    }
  }
  odometry::io::write_png8((root / "png" / "rgb.png").string(), crop);
  odometry::io::write_png8((root / "png" / "gray.png").string(), gray);
  odometry::io::write_png16((root / "png" / "depth.png").string(), dcrop);

  write_text(root / "conic_json" / "lp_dense.json",
             R"({"c": [-1, -1], "G": [[1, 2], [3, 1], [-1, 0], [0, -1]], "h": [4, 6, 0, 0], "cones": {"l": 4}})");
  write_text(root / "conic_json" / "socp_triplets.json",
             R"({"c": [0, 0, 1], "A": [[1, 1, 0]], "b": [1],)"
             R"( "G": {"rows": 3, "cols": 3, "triplets": [[0, 2, -1], [1, 0, -1], [2, 1, -1]]},)"
             R"( "h": [0, 0, 0], "cones": {"l": 0, "q": [3]}})");
  fs::remove_all(scratch);
}

}  // namespace bivo::fuzz
