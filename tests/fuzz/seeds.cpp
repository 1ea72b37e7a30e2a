// Seed corpora for the fuzz targets, made by the project itself: a small rendered sequence
// (its lists and ground truth, crops of its frames as PNGs), generated hand-held motion and
// the conic problems of docs/conic.md's format, and the same problems plus the paper's SOCP of a
// synthetic step written as CBF.
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <vector>

#include "experiments/conic_files/conic_file.h"
#include "harnesses.h"
#include "odometry/io/png_io.h"
#include "odometry/io/trajectory.h"
#include "odometry/synth/motion.h"
#include "odometry/synth/sequence.h"
#include "solvers/step/qcqp_socp.h"
#include "tests/support/synthetic_qcqp.h"

namespace bivo::fuzz {
namespace {

namespace fs = std::filesystem;

void copy_into(const fs::path& from, const fs::path& dir, const std::string& name) {
  fs::copy_file(from, dir / name, fs::copy_options::overwrite_existing);
}

void write_text(const fs::path& file, const std::string& text) { std::ofstream(file) << text; }

// A conic problem of the IPM (min c^T x, A x = b, G x + s = h, s in R+^l x Q..) as CBF:
// x free; the rows A x - b in L=, then h - G x in L+ (l rows) and one Q block per cone.
void write_cbf(const fs::path& file, const solvers::conic::ConicProblem& p) {
  using solvers::conic::SparseMatrix;
  const int n = p.num_variables(), eq = p.num_equalities(), l = p.cones.nonnegative;
  std::vector<std::string> cones, a, b, c;
  if (eq > 0) cones.push_back("L= " + std::to_string(eq));
  if (l > 0) cones.push_back("L+ " + std::to_string(l));
  for (int q : p.cones.soc) cones.push_back("Q " + std::to_string(q));
  std::ostringstream v;
  v << std::setprecision(17);
  const auto entry = [&v](std::vector<std::string>& out, const std::string& index, double value) {
    v.str("");
    v << index << " " << value;
    out.push_back(v.str());
  };
  for (int j = 0; j < n; ++j) {
    if (p.c[j] != 0.0) entry(c, std::to_string(j), p.c[j]);
  }
  const auto matrix = [&](const SparseMatrix& M, int row0, double sign) {
    for (int j = 0; j < M.outerSize(); ++j) {
      for (SparseMatrix::InnerIterator it(M, j); it; ++it) {
        entry(a, std::to_string(row0 + it.row()) + " " + std::to_string(j), sign * it.value());
      }
    }
  };
  matrix(p.A, 0, 1.0);
  matrix(p.G, eq, -1.0);
  for (int i = 0; i < eq; ++i) {
    if (p.b[i] != 0.0) entry(b, std::to_string(i), -p.b[i]);
  }
  for (int i = 0; i < p.num_cone_rows(); ++i) {
    if (p.h[i] != 0.0) entry(b, std::to_string(eq + i), p.h[i]);
  }
  std::ofstream out(file);
  out << "# written by bivo_fuzz_seeds\nVER\n3\n\nOBJSENSE\nMIN\n\nVAR\n"
      << n << " 1\nF " << n << "\n\nCON\n"
      << eq + p.num_cone_rows() << " " << cones.size() << "\n";
  for (const auto& line : cones) out << line << "\n";
  const auto block = [&out](const char* key, const std::vector<std::string>& lines) {
    out << "\n" << key << "\n" << lines.size() << "\n";
    for (const auto& line : lines) out << line << "\n";
  };
  block("OBJACOORD", c);
  block("ACOORD", a);
  block("BCOORD", b);
}

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

  // CBF: the two JSON problems, the paper's SOCP of a 12-pixel synthetic step in the full and
  // the compressed form, and the cone kinds and keywords the IPM form has no JSON for.
  for (const char* name : {"lp_dense", "socp_triplets"}) {
    write_cbf(root / "cbf" / (std::string(name) + ".cbf"),
              experiments::read_conic_json((root / "conic_json" / (std::string(name) + ".json")).string()));
  }
  namespace conic = solvers::conic;
  const conic::SyntheticStep step = conic::make_synthetic_step(12, 7);
  write_cbf(root / "cbf" / "paper_socp_full.cbf",
            conic::full_qcqp_socp(*step.lin.full1, *step.lin.full2, step.epsilon));
  write_cbf(root / "cbf" / "paper_socp_compressed.cbf",
            conic::compressed_qcqp_socp(conic::factor_from_model(step.lin.f1), conic::factor_from_model(step.lin.f2),
                                        step.epsilon));
  write_text(root / "cbf" / "rotated_max.cbf",
             "VER\n4\nOBJSENSE\nMAX\nVAR\n4 2\nL- 1\nQR 3\nCON\n2 2\nL+ 1\nL= 1\nOBJACOORD\n2\n0 1\n3 -1\n"
             "OBJBCOORD\n0.5\nACOORD\n3\n0 0 -1\n1 1 1\n1 2 -2\nBCOORD\n2\n0 4\n1 1\n");
  fs::remove_all(scratch);
}

}  // namespace bivo::fuzz
