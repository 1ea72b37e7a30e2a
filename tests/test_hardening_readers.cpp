// Hostile input to the readers, one test per reproducer, named after the input:
// each now ends in a bivo::Error naming the file and the value, never a crash, an
// allocation the input alone decides, or a silently wrong value.
#include <png.h>
#include <sys/stat.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <tuple>

#include <gtest/gtest.h>

#include "experiments/conic_files/conic_file.h"
#include "odometry/io/atomic_file.h"
#include "odometry/io/input_limits.h"
#include "odometry/io/metrics.h"
#include "odometry/io/png_io.h"
#include "odometry/io/trajectory.h"
#include "odometry/io/tum_dataset.h"
#include "solvers/conic/cones.h"
#include "test_support.h"

namespace fs = std::filesystem;
using bivo::testing::contains;
using namespace bivo;
using bivo::testing::error_of;

namespace {

// One folder per test process: ctest runs tests side by side, and the output tests look
// for temporaries left beside their targets.
const std::string& scratch() {
  static const bivo::testing::TempDir dir("bivo_hardening");
  static const std::string path = dir.path.string() + "/";
  return path;
}

std::string temp(const std::string& name) { return scratch() + name; }

std::string write_text(const std::string& name, const std::string& text) {
  const std::string path = temp(name);
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

struct LimitsGuard {  // restores the process-wide limits after a test changes them
  odometry::io::InputLimits saved = odometry::io::input_limits();
  ~LimitsGuard() { odometry::io::input_limits() = saved; }
};

// The definition of associate.py: every candidate pair, sorted by (|dt|, i, j), taken greedily.
std::vector<std::pair<int, int>> associate_by_sorting(const std::vector<double>& a, const std::vector<double>& b,
                                                      double max_dt) {
  std::vector<std::tuple<double, int, int>> c;
  for (int i = 0; i < int(a.size()); ++i) {
    for (int j = 0; j < int(b.size()); ++j) {
      if (std::abs(a[i] - b[j]) < max_dt) c.emplace_back(std::abs(a[i] - b[j]), i, j);
    }
  }
  std::sort(c.begin(), c.end());
  std::vector<char> ua(a.size()), ub(b.size());
  std::vector<std::pair<int, int>> m;
  for (const auto& [d, i, j] : c) {
    if (ua[i] || ub[j]) continue;
    ua[i] = ub[j] = 1;
    m.emplace_back(i, j);
  }
  std::sort(m.begin(), m.end());
  return m;
}

}  // namespace

// Item 1: cone sizes adding up past 2^31 wrapped to the row count.
TEST(HardeningConic, ConeSizes2147483647Plus2147483647Plus3) {
  const std::string file =
      write_text("cones.json", R"({"c":[1],"G":[[1]],"h":[1],"cones":{"q":[2147483647,2147483647,3]}})");
  const std::string msg = error_of([&] { experiments::read_conic_json(file); });
  EXPECT_TRUE(contains(msg, file)) << msg;
  EXPECT_TRUE(contains(msg, "4294967297")) << msg;
  solvers::conic::ConeSpec spec;
  spec.soc = {2147483647, 2147483647, 3};
  EXPECT_THROW(spec.dim(), Error);
  EXPECT_THROW(solvers::conic::ConeProduct{spec}, Error);
}

// Item 5: a deeply nested value in a number field (400 KB) overflowed the stack when the
// error message serialised it; messages are now short whatever the value.
TEST(HardeningConic, NestedArrays200000DeepInANumberField) {
  const std::string deep = std::string(200000, '[') + "1" + std::string(200000, ']');
  const std::string file = write_text("deep.json", R"({"c":[)" + deep + R"(],"G":[[1]],"h":[1],"cones":{"l":1}})");
  const std::string msg = error_of([&] { experiments::read_conic_json(file); });
  EXPECT_TRUE(contains(msg, "nested")) << msg;
  EXPECT_LT(msg.size(), 400u);
  const std::string shallow = write_text("nested.json", R"({"c":[[[[1]]]],"G":[[1]],"h":[1],"cones":{"l":1}})");
  const std::string m2 = error_of([&] { experiments::read_conic_json(shallow); });
  EXPECT_TRUE(contains(m2, "c[0] is not a number (an array of 1 entries)")) << m2;
  const std::string text = write_text("string.json", R"({"c":[")" + std::string(100000, 'x') + R"("],"cones":{}})");
  EXPECT_LT(error_of([&] { experiments::read_conic_json(text); }).size(), 300u);
}

// Item 9: JSON numbers converted to int without range checks (undefined behaviour).
TEST(HardeningConic, RowsMinus2147483649AndIndex1e300AndConeL3e9) {
  const std::string rows =
      write_text("rows.json", R"({"c":[1,1],"G":{"rows":-2147483649,"cols":2,"triplets":[]},"h":[],"cones":{}})");
  std::string msg = error_of([&] { experiments::read_conic_json(rows); });
  EXPECT_TRUE(contains(msg, "G.rows must be an integer in 0..2147483647")) << msg;
  const std::string index =
      write_text("index.json", R"({"c":[1],"G":{"rows":1,"cols":1,"triplets":[[1e300,0,1]]},"h":[1],"cones":{"l":1}})");
  msg = error_of([&] { experiments::read_conic_json(index); });
  EXPECT_TRUE(contains(msg, "triplets[0][0] must be an integer in 0..2147483647, got 1e+300")) << msg;
  const std::string cone = write_text("l.json", R"({"c":[1],"G":[[1]],"h":[1],"cones":{"l":3e9}})");
  msg = error_of([&] { experiments::read_conic_json(cone); });
  EXPECT_TRUE(contains(msg, "cones.l must be an integer")) << msg;
  const std::string half = write_text("half.json", R"({"c":[1],"G":[[1]],"h":[1],"cones":{"q":[1.5]}})");
  EXPECT_TRUE(contains(error_of([&] { experiments::read_conic_json(half); }), "cones.q[0]"));
}

// Item 13 (library side): a folder given as the conic file.
TEST(HardeningConic, FolderAsProblemFile) {
  const std::string msg = error_of([] { experiments::read_conic_json(::testing::TempDir()); });
  EXPECT_TRUE(contains(msg, "is a folder")) << msg;
}

// Item 7: a header-only PNG claiming 100000 x 100000 pixels asked for 30 GB.
TEST(HardeningPng, HeaderOnly100000x100000) {
  const std::string file = write_text("huge.png", bivo::testing::png_header_only(100000, 100000));
  const std::string msg = error_of([&] { odometry::io::read_png8(file); });
  EXPECT_TRUE(contains(msg, file)) << msg;
  EXPECT_TRUE(contains(msg, "100000 x 100000")) << msg;
  EXPECT_TRUE(contains(msg, "--max-image-pixels")) << msg;
  // With the limit raised the decoder still allocates only what the data delivers: the
  // missing image data is reported as corruption, not as a failed allocation.
  LimitsGuard guard;
  odometry::io::input_limits().max_image_pixels = std::int64_t{1} << 40;
  const std::string raised = error_of([&] { odometry::io::read_png8(file); });
  EXPECT_TRUE(contains(raised, "corrupt PNG")) << raised;
  const std::string depth = write_text("huge16.png", bivo::testing::png_header_only(60000, 60000));
  EXPECT_TRUE(contains(error_of([&] { odometry::io::read_png16(depth); }), depth));
}

// The process's peak virtual size in kB (/proc/self/status VmPeak), 0 where unknown.
long vm_peak_kb() {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("VmPeak:", 0) == 0) return std::stol(line.substr(7));
  }
  return 0;
}

// Found by fuzz-ci: 67 bytes whose sPLT chunk claims 1,936,946,035 bytes made libpng allocate
// them before reading any (an out-of-memory finding). The reader skips ancillary chunks.
TEST(HardeningPng, AncillaryChunkClaiming1point9GB) {
  const std::string bytes = std::string(
                                "\x89PNG\r\n\x1a\n"  // signature, then IHDR: 3 x 2 palette
                                "\x00\x00\x00\x0dIHDR\x00\x00\x00\x03\x00\x00\x00\x02\x08\x03\x00\x00\x00"
                                "\xaa\xaa\x96\x28",
                                33) +
                            "ssss" + "sPLT" + "E\xffG\r\n";  // length 0x73737373
  const std::string file = write_text("splt.png", bytes);
  const long before = vm_peak_kb();
  const std::string msg = error_of([&] { odometry::io::read_png8(file); });
  EXPECT_TRUE(contains(msg, "corrupt PNG '" + file + "'")) << msg;
  if (before > 0) {
    EXPECT_LT(vm_peak_kb() - before, 256L * 1024) << "the chunk's claimed length was allocated";
  }
}

// Item 12: a valid palette PNG with a tRNS chunk was rejected as having 4 channels.
TEST(HardeningPng, PaletteWithTransparencyChunk) {
  const std::string file = temp("palette_trns.png");
  std::FILE* f = std::fopen(file.c_str(), "wb");
  ASSERT_NE(f, nullptr);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  ASSERT_FALSE(setjmp(png_jmpbuf(png)));
  png_init_io(png, f);
  png_set_IHDR(png, info, 3, 2, 8, PNG_COLOR_TYPE_PALETTE, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_color palette[3] = {{255, 0, 0}, {0, 255, 0}, {10, 20, 30}};
  png_set_PLTE(png, info, palette, 3);
  png_byte alpha[1] = {0};  // index 0 fully transparent
  png_set_tRNS(png, info, alpha, 1, nullptr);
  png_write_info(png, info);
  png_byte rows[2][3] = {{0, 1, 2}, {2, 1, 0}};
  for (auto& row : rows) png_write_row(png, row);
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  std::fclose(f);

  const odometry::io::Png8 img = odometry::io::read_png8(file);
  ASSERT_EQ(img.channels, 3);
  ASSERT_EQ(img.width, 3);
  ASSERT_EQ(img.height, 2);
  const std::vector<std::uint8_t> want = {255, 0, 0, 0, 255, 0, 10, 20, 30, 10, 20, 30, 0, 255, 0, 255, 0, 0};
  EXPECT_EQ(img.data, want);
}

// Item 8: association memory was quadratic in duplicated timestamps or in max_dt.
TEST(HardeningAssociation, RgbList50000LinesOfOneTimestamp) {
  std::string text;
  for (int k = 0; k < 50000; ++k) text += "1.0 rgb/a.png\n";
  const std::string file = write_text("dup_rgb.txt", text);
  const std::string msg = error_of([&] { odometry::io::read_file_list(file); });
  EXPECT_TRUE(contains(msg, file + ":2")) << msg;
  EXPECT_TRUE(contains(msg, "repeats line 1")) << msg;
}

TEST(HardeningAssociation, MaxDt1e9Over200000StampsEach) {
  // Every pair is a candidate: 4e10 of them (640 GB listed); the matcher keeps O(n).
  std::vector<double> a, b;
  for (int k = 0; k < 200000; ++k) {
    a.push_back(1000.0 + 0.01 * k);
    b.push_back(1000.004 + 0.01 * k);
  }
  const auto m = odometry::io::associate_timestamps(a, b, 1e9);
  ASSERT_EQ(m.size(), a.size());
  for (int k = 0; k < 200000; k += 9973) EXPECT_EQ(m[k], std::make_pair(k, k));
}

TEST(HardeningAssociation, EqualsTheCandidateSortingDefinition) {
  // Random lists with exact ties (a quarter-grid of stamps, shared values) against the
  // quadratic definition, for small and huge max_dt.
  std::mt19937 rng(5);
  for (int trial = 0; trial < 300; ++trial) {
    std::vector<double> a, b;
    for (double t = 0; t < 6; t += 0.25) {
      if (rng() % 2) a.push_back(t);
      if (rng() % 2) b.push_back(t);
    }
    for (double max_dt : {0.2, 0.3, 0.5, 0.8, 1e9}) {
      ASSERT_EQ(odometry::io::associate_timestamps(a, b, max_dt), associate_by_sorting(a, b, max_dt))
          << "trial " << trial << " max_dt " << max_dt;
    }
  }
  EXPECT_TRUE(contains(error_of([] { odometry::io::associate_timestamps({1, 1}, {1}, 1); }), "strictly increasing"));
}

TEST(HardeningAssociation, AteWithMaxDt1e9OverLongTrajectories) {
  odometry::io::Trajectory gt, est;
  for (int k = 0; k < 100000; ++k) {
    odometry::io::StampedPose p;
    p.timestamp = 0.01 * k;
    p.T_wc.translation() = Eigen::Vector3d(std::sin(0.001 * k), std::cos(0.002 * k), 0.0001 * k);
    gt.push_back(p);
    est.push_back(p);
  }
  odometry::io::AteOptions o;
  o.max_dt = 1e9;
  EXPECT_NEAR(odometry::io::absolute_trajectory_error(gt, est, o).rmse, 0.0, 1e-9);
}

// Lists longer than the limit are refused, naming the flag that raises it.
TEST(HardeningLists, FourLinesWithLimitThree) {
  LimitsGuard guard;
  odometry::io::input_limits().max_list_entries = 3;
  const std::string file = write_text("long.txt", "1 a.png\n2 b.png\n3 c.png\n4 d.png\n");
  const std::string msg = error_of([&] { odometry::io::read_file_list(file); });
  EXPECT_TRUE(contains(msg, file)) << msg;
  EXPECT_TRUE(contains(msg, "--max-list-entries")) << msg;
}

TEST(HardeningLists, FolderAsList) {
  const std::string msg = error_of([] { odometry::io::read_file_list(::testing::TempDir()); });
  EXPECT_TRUE(contains(msg, "cannot read list")) << msg;
}

// Item 14: quaternion components above ~1e154 overflowed the norm and read as identity.
TEST(HardeningTrajectory, QuaternionComponents1e200) {
  const std::string file = write_text("big_q.txt", "0 1 2 3 1e200 0 0 1e200\n1 0 0 0 0 0 0 1e-300\n");
  // Line 2's quaternion is too small to be a rotation: refused, naming the line.
  EXPECT_TRUE(contains(error_of([&] { odometry::io::read_tum_trajectory(file); }), "big_q.txt:2"));
  const std::string ok = write_text("big_q2.txt", "0 1 2 3 1e200 0 0 1e200\n1 0 0 0 -1e300 0 0 0\n");
  const auto t = odometry::io::read_tum_trajectory(ok);
  ASSERT_EQ(t.size(), 2u);
  // (w, x) = (1, 1)/sqrt 2: 90 degrees about x.
  const Eigen::Matrix3d Rx = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  EXPECT_LT((t[0].T_wc.linear() - Rx).norm(), 1e-12);
  EXPECT_LT((t[1].T_wc.linear() - Eigen::Matrix3d(Eigen::Vector3d(1, -1, -1).asDiagonal())).norm(), 1e-12);
}

TEST(HardeningTrajectory, EqualTimestampsKeepTheLaterPoseAsTumTools) {
  // TUM's evaluate scripts key poses by stamp in a dict: the later line wins.
  const std::string conflict = write_text("conflict.txt", "# gt\n1 0 0 0 0 0 0 1\n1 5 0 0 0 0 0 1\n2 6 0 0 0 0 0 1\n");
  const auto t = odometry::io::read_tum_trajectory(conflict);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[0].T_wc.translation().x(), 5.0);
  EXPECT_EQ(t[1].timestamp, 2.0);
  const std::string repeat = write_text("repeat.txt", "1 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n2 0 0 0 0 0 0 1\n");
  EXPECT_EQ(odometry::io::read_tum_trajectory(repeat).size(), 2u);
  // Earlier stamps after later ones are still refused.
  const std::string unsorted = write_text("unsorted.txt", "2 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n");
  EXPECT_TRUE(contains(error_of([&] { odometry::io::read_tum_trajectory(unsorted); }), "unsorted.txt:2"));
}

TEST(HardeningTrajectory, RealFreiburg2GroundTruthWithRepeatedStamps) {
  const std::string gt = std::string(BIVO_SHARED_DIR) + "/data/trajectories/rgbd_dataset_freiburg2_xyz-groundtruth.txt";
  if (!std::filesystem::exists(gt)) GTEST_SKIP() << "shared data absent: " << gt;
  // Oracle: the distinct stamps of the file, counted here independently of the reader.
  std::ifstream in(gt);
  std::set<std::string> stamps;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line[0] != '#') stamps.insert(line.substr(0, line.find(' ')));
  }
  const auto t = odometry::io::read_tum_trajectory(gt);
  EXPECT_EQ(t.size(), stamps.size());
  for (std::size_t k = 1; k < t.size(); ++k) ASSERT_LT(t[k - 1].timestamp, t[k].timestamp);
}

// Item 4: outputs were renamed over whatever the path named.
TEST(HardeningOutputs, SymlinkFifoAndFolderAreNeverReplaced) {
  const std::string target = write_text("precious.txt", "keep me\n");
  const std::string link = temp("link.txt");
  const std::string fifo = temp("fifo");
  const std::string folder = temp("folder");
  fs::remove(link);
  fs::remove(fifo);
  fs::create_directories(folder);
  fs::create_symlink(target, link);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  for (const std::string& path : {link, fifo, folder}) {
    const std::string msg =
        error_of([&] { odometry::io::write_file_atomically(path, [](std::ostream& o) { o << "new\n"; }); });
    EXPECT_TRUE(contains(msg, "refusing to write '" + path + "'")) << msg;
  }
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_EQ(fs::status(fifo).type(), fs::file_type::fifo);
  EXPECT_TRUE(fs::is_directory(folder));
  std::ifstream in(target);
  std::string content;
  std::getline(in, content);
  EXPECT_EQ(content, "keep me");
  odometry::io::Png8 img;
  img.width = img.height = 1;
  img.channels = 1;
  img.data = {7};
  EXPECT_TRUE(contains(error_of([&] { odometry::io::write_png8(link, img); }), "symbolic link"));
  EXPECT_TRUE(fs::is_symlink(link));
  // Nothing beside the targets either (no temporaries left).
  for (const auto& e : fs::directory_iterator(scratch())) {
    EXPECT_FALSE(contains(e.path().filename().string(), ".tmp")) << e.path();
  }
}

TEST(HardeningOutputs, StagedOutputsAppearTogetherOrNotAtAll) {
  const std::string first = temp("staged_first.txt"), folder = temp("staged_folder");
  fs::remove(first);
  fs::create_directories(folder);
  {
    odometry::io::StagedOutputs out;
    out.add(first, [](std::ostream& o) { o << "1\n"; });
    EXPECT_THROW(out.add(folder, [](std::ostream& o) { o << "2\n"; }), Error);
  }  // abandoned: the first output's temporary is removed, the target never appears
  EXPECT_FALSE(fs::exists(first));
  odometry::io::StagedOutputs out;
  out.add(first, [](std::ostream& o) { o << "1\n"; });
  EXPECT_FALSE(fs::exists(first));
  out.commit();
  EXPECT_TRUE(fs::is_regular_file(first));
}
