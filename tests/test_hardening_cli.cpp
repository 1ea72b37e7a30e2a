// Hostile command lines through the built `bivo`, each test named after its
// reproducer: a clear error naming the flag, file or value, a non-zero exit, never
// "internal error" or a crash, and no output left behind or replaced. Valid but extreme
// windows run normally.
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "odometry/io/png_io.h"
#include "odometry/io/trajectory.h"
#include "tests/support/cli_suite.h"

namespace fs = std::filesystem;
using bivo::testing::contains;
using bivo::testing::slurp;
using namespace bivo;
using bivo::testing::BivoRun;
using bivo::testing::expect_clear_error;

namespace {

// One 4-frame synthetic sequence shared by the tests; each test works in its own folder.
class HardeningCli : public bivo::testing::CliSuite {
 protected:
  static void SetUpTestSuite() { render_suite("bivo_hardening_cli"); }

  // A private copy of the sequence to damage.
  fs::path copy_sequence() const {
    const fs::path copy = dir_ / fs::path(sequence_).filename();
    fs::copy(sequence_, copy, fs::copy_options::recursive);
    return copy;
  }
  static std::vector<std::string> list_column(const fs::path& list, int column) {
    std::vector<std::string> out;
    std::istringstream in(slurp(list));
    for (std::string line; std::getline(in, line);) {
      if (line.empty() || line[0] == '#') continue;
      std::istringstream words(line);
      std::string w;
      for (int k = 0; k <= column; ++k) words >> w;
      out.push_back(w);
    }
    return out;
  }
  // Only the files named remain in this test's folder.
  void expect_only(std::vector<std::string> names) const {
    for (const auto& e : fs::directory_iterator(dir_)) {
      const std::string name = e.path().filename().string();
      EXPECT_NE(std::find(names.begin(), names.end(), name), names.end()) << "left behind: " << e.path();
    }
  }
};

}  // namespace

// Item 1.
TEST_F(HardeningCli, ConicConesQ2147483647Twice) {
  std::ofstream(dir_ / "p.json") << R"({"c":[1],"G":[[1]],"h":[1],"cones":{"q":[2147483647,2147483647,3]}})";
  expect_clear_error(bivo("conic " + q(dir_ / "p.json")), "dimensions sum to 4294967297");
}

// Item 2.
TEST_F(HardeningCli, RunFirstFrame2147483647) {
  const BivoRun r =
      bivo("run " + q(sequence_) + " --method single --first-frame 2147483647 --output " + q(dir_ / "t.txt"));
  expect_clear_error(r, "first frame 2147483647 leaves fewer than 2");
  expect_only({});
}

// Item 3: a valid window reaching past the end runs to the end.
TEST_F(HardeningCli, RunFirstFrame1MaxFrames2147483647) {
  const BivoRun r = bivo("run " + q(sequence_) + " --method single --first-frame 1 --max-frames 2147483647 --output " +
                         q(dir_ / "t.txt"));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "frames=3 ")) << r.out;
  EXPECT_EQ(odometry::io::read_tum_trajectory((dir_ / "t.txt").string()).size(), 3u);
}

// Item 4: a symlink, FIFO or device node at the output path was replaced by a plain file.
TEST_F(HardeningCli, RunOutputSymlinkFifoAndDeviceNode) {
  std::ofstream(dir_ / "precious.txt") << "keep\n";
  fs::create_symlink(dir_ / "precious.txt", dir_ / "link.txt");
  ASSERT_EQ(::mkfifo((dir_ / "fifo").c_str(), 0600), 0);
  std::vector<std::pair<std::string, std::string>> targets = {{"link.txt", "symbolic link"}, {"fifo", "FIFO"}};
  // A character device like /dev/null, made here (root only) so no system node is at risk.
  if (::mknod((dir_ / "null").c_str(), S_IFCHR | 0600, makedev(1, 3)) == 0) targets.push_back({"null", "device"});
  for (const auto& [name, kind] : targets) {
    const BivoRun r = bivo("run " + q(sequence_) + " --method single --output " + q(dir_ / name));
    expect_clear_error(r, "--output: refusing to write '" + (dir_ / name).string() + "'");
    EXPECT_TRUE(contains(r.err, kind)) << r.err;
  }
  EXPECT_TRUE(fs::is_symlink(dir_ / "link.txt"));
  EXPECT_EQ(slurp(dir_ / "precious.txt"), "keep\n");
  EXPECT_EQ(fs::symlink_status(dir_ / "fifo").type(), fs::file_type::fifo);
  expect_only({"precious.txt", "link.txt", "fifo", "null"});
}

// Item 5.
TEST_F(HardeningCli, ConicNestedArrays200000Deep) {
  std::ofstream(dir_ / "deep.json") << R"({"c":[)" << std::string(200000, '[') << 1 << std::string(200000, ']')
                                    << R"(],"G":[[1]],"h":[1],"cones":{"l":1}})";
  const BivoRun r = bivo("conic " + q(dir_ / "deep.json"));
  expect_clear_error(r, "nested more than");
  EXPECT_LT(r.err.size(), 500u);
}

// Item 6: one frame without valid depth (or texture) aborted weighted and tykkala runs.
TEST_F(HardeningCli, WeightedAndTykkalaOnAFrameWithoutDepth) {
  const fs::path seq = copy_sequence();
  const std::string depth_file = list_column(seq / "depth.txt", 1).at(1);
  odometry::io::Png16 depth = odometry::io::read_png16((seq / depth_file).string());
  std::fill(depth.data.begin(), depth.data.end(), 0);
  odometry::io::write_png16((seq / depth_file).string(), depth);
  for (const char* method : {"weighted", "tykkala", "single"}) {
    const fs::path out = dir_ / (std::string(method) + ".txt"), log = dir_ / (std::string(method) + ".csv");
    const BivoRun r = bivo("run " + q(seq) + " --method " + method + " --output " + q(out) + " --log " + q(log));
    ASSERT_EQ(r.status, 0) << method << ": " << r.err;
    EXPECT_TRUE(contains(r.out, "frames=4 ")) << r.out;
    EXPECT_FALSE(contains(r.out, "failures=0")) << method << ": " << r.out;  // pair 1 has no reference depth
    EXPECT_EQ(odometry::io::read_tum_trajectory(out.string()).size(), 4u);
    EXPECT_TRUE(contains(slurp(log), "motion prior used")) << slurp(log);
  }
}

TEST_F(HardeningCli, WeightedOnAFrameWithoutTexture) {
  const fs::path seq = copy_sequence();
  const std::string rgb_file = list_column(seq / "rgb.txt", 1).at(1);
  odometry::io::Png8 rgb = odometry::io::read_png8((seq / rgb_file).string());
  std::fill(rgb.data.begin(), rgb.data.end(), 128);
  odometry::io::write_png8((seq / rgb_file).string(), rgb);
  const BivoRun r = bivo("run " + q(seq) + " --method weighted --log " + q(dir_ / "w.csv"));
  ASSERT_EQ(r.status, 0) << r.err;
  // Both pairs of the frame fall back to the prior: as reference it leaves weighted's lambda
  // undefined; as current image it has no contrast for F_I.
  EXPECT_TRUE(contains(r.out, "failures=2")) << r.out;
  EXPECT_TRUE(contains(slurp(dir_ / "w.csv"), "lambda undefined")) << slurp(dir_ / "w.csv");
  EXPECT_TRUE(contains(slurp(dir_ / "w.csv"), "without contrast")) << slurp(dir_ / "w.csv");
}

// Item 7: the PNG header alone decided the allocation ("internal error: std::bad_alloc").
TEST_F(HardeningCli, RunOnAPngHeaderClaiming100000x100000) {
  const fs::path seq = copy_sequence();
  const std::string rgb_file = list_column(seq / "rgb.txt", 1).at(2);
  std::ofstream(seq / rgb_file, std::ios::binary) << bivo::testing::png_header_only(100000, 100000);
  const BivoRun r = bivo("run " + q(seq) + " --method single --output " + q(dir_ / "t.txt"));
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_TRUE(contains(r.err, rgb_file)) << r.err;
  EXPECT_TRUE(contains(r.err, "100000 x 100000 exceeds the limit")) << r.err;
  EXPECT_FALSE(contains(r.err, "internal error")) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "t.txt"));
  // Raised by flag, the limit lets the header through; the missing data is then reported.
  const BivoRun raised = bivo("--max-image-pixels 100000000000 run " + q(seq) + " --method single");
  expect_clear_error(raised, "corrupt PNG");
}

TEST_F(HardeningCli, MaxImagePixelsFlagBelowTheFrameSize) {
  const BivoRun r = bivo("--max-image-pixels 1000 run " + q(sequence_) + " --method single");
  expect_clear_error(r, "exceeds the limit of 1000 pixels (raise with --max-image-pixels)");
  EXPECT_TRUE(contains(r.err, "640 x 480")) << r.err;
}

// Item 8: duplicated timestamps made association quadratic in memory.
TEST_F(HardeningCli, RunOnAnRgbListRepeatingOneTimestamp) {
  const fs::path seq = copy_sequence();
  fs::remove(seq / "associations.txt");
  std::string text = "# rgb\n";
  for (int k = 0; k < 20000; ++k) text += "1.0 rgb/x.png\n";
  std::ofstream(seq / "rgb.txt") << text;
  expect_clear_error(bivo("run " + q(seq) + " --method single"), "rgb.txt:3: timestamp 1.0 repeats line 2");
}

TEST_F(HardeningCli, EvalWithMaxDt1e9) {
  odometry::io::Trajectory t;
  for (int k = 0; k < 20000; ++k) {
    odometry::io::StampedPose p;
    p.timestamp = 0.01 * k;
    p.T_wc.translation() = Eigen::Vector3d(std::sin(0.01 * k), 0.001 * k, 0.0);
    t.push_back(p);
  }
  const std::string gt = (dir_ / "long.txt").string();
  odometry::io::write_tum_trajectory(gt, t);
  const BivoRun r = bivo("eval " + q(gt) + " " + q(gt) + " --max-dt 1e9");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto at = r.out.find("ate=");
  ASSERT_NE(at, std::string::npos) << r.out;
  EXPECT_LT(std::stod(r.out.substr(at + 4)), 1e-9) << r.out;  // every pose matched to itself
}

// Item 9.
TEST_F(HardeningCli, ConicFeastolNanAndRowsMinus2147483649) {
  std::ofstream(dir_ / "lp.json") << R"({"c":[1],"G":[[-1]],"h":[0],"cones":{"l":1}})";
  for (const char* flag : {"--feastol nan", "--feastol inf", "--reltol -nan", "--abstol nan"}) {
    const BivoRun r = bivo("conic " + q(dir_ / "lp.json") + " " + flag);
    EXPECT_NE(r.status, 0) << flag;
    EXPECT_TRUE(contains(r.err, "must be a finite number")) << flag << ": " << r.err;
  }
  std::ofstream(dir_ / "rows.json") << R"({"c":[1,1],"G":{"rows":-2147483649,"cols":2,"triplets":[]},"cones":{}})";
  expect_clear_error(bivo("conic " + q(dir_ / "rows.json")), "G.rows must be an integer in 0..2147483647");
}

// Item 10: synth validated after generating motion; bad sensor values gave NaN pixels.
TEST_F(HardeningCli, SynthFlagsOutOfRange) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--fps 0", "--fps must be in (0, 1e6]"},
      {"--fps 1e7", "--fps must be in (0, 1e6]"},
      {"--fps nan", "--fps must be in (0, 1e6]"},
      {"--fps 1e-300", "of generated motion"},
      {"--start 1e308", "of generated motion"},
      {"--start -1", "--start must be a finite number"},
      {"--frames 2000000000", "--frames 2000000000: more than 1000000 entries"},
      {"--frames 0", "--frames must be >= 1"},
      {"--depth-noise nan", "depth noise coefficient"},
      {"--read-noise -1", "read noise"},
      {"--shot-noise -0.5", "shot-noise gain"},
      {"--max-range 0", "maximum range 0 m must exceed the minimum range 0.5 m"},
      {"--exposure-jitter 1e300", "exposure jitter"},
      {"--supersampling 100", "supersampling"},
      {"--threads 100000", "--threads must be in 0..256"},
  };
  for (const auto& [flags, message] : cases) {
    const fs::path out = dir_ / "out";
    const std::string frames = contains(flags, "--frames") ? "" : "--frames 3 ";
    const BivoRun r = bivo("synth --category structure_texture_near " + frames + flags + " --output " + q(out));
    EXPECT_EQ(r.status, 1) << flags << ": " << r.err;
    EXPECT_TRUE(contains(r.err, message)) << flags << ": " << r.err;
    EXPECT_FALSE(contains(r.err, "internal error")) << flags << ": " << r.err;
    EXPECT_FALSE(fs::exists(out)) << flags;
  }
}

// Item 11: the outputs of a run are one set, disjoint from its inputs.
TEST_F(HardeningCli, RunOutputXLogX) {
  const BivoRun r =
      bivo("run " + q(sequence_) + " --method single --output " + q(dir_ / "x") + " --log " + q(dir_ / "x"));
  expect_clear_error(r, "--log '" + (dir_ / "x").string() + "' and --output");
  expect_only({});
}

TEST_F(HardeningCli, RunLogIsAFolder) {
  fs::create_directories(dir_ / "logs");
  const BivoRun r =
      bivo("run " + q(sequence_) + " --method single --output " + q(dir_ / "t.txt") + " --log " + q(dir_ / "logs"));
  expect_clear_error(r, "--log: refusing to write");
  expect_only({"logs"});  // no trajectory left behind
}

TEST_F(HardeningCli, RunOutputIsTheSequencesGroundtruth) {
  const fs::path seq = copy_sequence();
  const std::string before = slurp(seq / "groundtruth.txt");
  const BivoRun r = bivo("run " + q(seq) + " --method single --output " + q(seq / "groundtruth.txt"));
  expect_clear_error(r, "is an input of this run");
  EXPECT_EQ(slurp(seq / "groundtruth.txt"), before);
  const BivoRun l = bivo("run " + q(seq) + " --method single --log " + q(seq / "rgb.txt"));
  expect_clear_error(l, "--log");
  const BivoRun e = bivo("eval " + q(seq / "groundtruth.txt") + " " + q(seq / "groundtruth.txt") + " --output " +
                         q(seq / "groundtruth.txt"));
  expect_clear_error(e, "is an input of this run (groundtruth");
  EXPECT_EQ(slurp(seq / "groundtruth.txt"), before);
}

// Item 13: filesystem errors surfaced as "internal error"; --every overflowed.
TEST_F(HardeningCli, ParetoOutputIsAFile) {
  std::ofstream(dir_ / "file") << "x";
  expect_clear_error(bivo("pareto " + q(sequence_) + " --pair 0 --no-plots --output " + q(dir_ / "file")),
                     "--output '" + (dir_ / "file").string() + "' exists and is not a folder");
  expect_clear_error(bivo("pareto " + q(sequence_) + " --pair 0 --no-plots --output " + q(dir_ / "file" / "sub")),
                     "is not a folder");
  expect_clear_error(bivo("sweep --sequences " + q(sequence_) + " --output " + q(dir_ / "file")),
                     "exists and is not a folder");
}

TEST_F(HardeningCli, ParetoPair2147483647AndEvery2147483647) {
  expect_clear_error(bivo("pareto " + q(sequence_) + " --pair 2147483647 --no-plots --output " + q(dir_ / "p")),
                     "--pair 2147483647: sequence");
  EXPECT_FALSE(fs::exists(dir_ / "p"));
  const BivoRun r =
      bivo("pareto " + q(sequence_) + " --every 2147483647 --no-plots --points 2 --levels 2 --output " + q(dir_ / "e"));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir_ / "e" / "pareto_pair0.json"));
  EXPECT_FALSE(fs::exists(dir_ / "e" / "pareto_pair2147483647.json"));
}

// A front swept on the depth as taken cannot score a method run on retimed depth.
TEST_F(HardeningCli, ParetoRefusesRetimedDepth) {
  for (const char* value : {"1", "2"}) {
    const BivoRun r =
        bivo("pareto " + q(sequence_) + " --pair 0 --no-plots --retime-depth " + value + " --output " + q(dir_ / "r"));
    expect_clear_error(r, "--retime-depth");
    EXPECT_FALSE(fs::exists(dir_ / "r"));
  }
}

TEST_F(HardeningCli, ParetoRefusesRollingShutterCorrection) {
  const BivoRun r =
      bivo("pareto " + q(sequence_) + " --pair 0 --no-plots --readout-time 0.02 --output " + q(dir_ / "r"));
  expect_clear_error(r, "--readout-time");
  EXPECT_FALSE(fs::exists(dir_ / "r"));
}

TEST_F(HardeningCli, ConicOnAFolder) { expect_clear_error(bivo("conic " + q(dir_)), "is a folder"); }

// Item 14: one timestamp with two poses was accepted silently.
TEST_F(HardeningCli, EvalGroundtruthWithOneTimestampTwice) {
  // As TUM's evaluate scripts (a dict keyed by stamp): the later pose holds, so an estimate
  // equal to the ground truth without the earlier pose has zero error.
  std::ofstream gt(dir_ / "gt.txt"), est(dir_ / "est.txt");
  for (const char* t : {"0", "0.5", "1", "1.5", "2", "2.5", "3"}) {
    if (std::string(t) == "1") gt << "1 99 0 0 0 0 0 1\n";
    gt << t << ' ' << t << " 0 0 0 0 0 1\n";
    est << t << ' ' << t << " 0 0 0 0 0 1\n";
  }
  gt.close();
  est.close();
  const BivoRun r = bivo("eval " + q(dir_ / "gt.txt") + " " + q(dir_ / "est.txt"));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "rpe_trans=0 rpe_rot=0 ate=0 pairs=4")) << r.out;
}

// Found by fuzz_cbf (tests/fuzz/regressions/cbf/var_and_con_1073741824.cbf): a 70-byte CBF
// file's VAR and CON headers asked for 2^31 rows (int overflow, then gigabytes).
TEST_F(HardeningCli, CbfVarAndCon1073741824) {
  const fs::path file = fs::path(BIVO_TESTS_DIR) / "fuzz" / "regressions" / "cbf" / "var_and_con_1073741824.cbf";
  expect_clear_error(bivo("conic " + q(file)),
                     "var_and_con_1073741824.cbf:5: 1073741824 variables + 0 constraints exceed the limit of "
                     "16777216 (raise with --max-conic-size)");
  const BivoRun over = bivo("--max-conic-size 1073741825 conic " + q(file));
  EXPECT_NE(over.status, 0);
  EXPECT_TRUE(contains(over.err, "--max-conic-size")) << over.err;
  expect_only({});
}

// depth-stats ran one pair for --pairs 0 or -1 and blamed the sequence's length for --gap 0.
TEST_F(HardeningCli, DepthStatsPairsAndGapBelowOne) {
  for (const char* flags : {"--pairs 0", "--pairs -1", "--gap 0"}) {
    expect_clear_error(bivo("depth-stats " + q(sequence_) + " " + flags), "not in range 1 to 1000000");
  }
}

// A frame window the tracker refuses failed every unit after the others had run (table,
// report, sweep, loso), the demo only after rendering its sequences, and pareto's lambda
// range and level inside each pair's unit: now refused before any work, nothing written.
TEST_F(HardeningCli, BadValuesAreRefusedBeforeAnyUnit) {
  const std::string seq = q(sequence_);
  const fs::path out = dir_ / "out";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"table --sequences " + seq + " --methods single weighted --max-frames -3", "got -3"},
      {"table --sequences " + seq + " --methods single --first-frame -2", "first frame must be >= 0, got -2"},
      {"sweep --sequences " + seq + " --max-frames 1", "got 1"},
      {"report --sequences " + seq + " --max-frames 4 --sweep-frames -3", "got -3"},
      {"loso --sequences " + seq + " " + seq + " --method robust --parameter trust --grid 1 --max-frames 0", "got 0"},
      {"demo --sweep-frames -3", "got -3"},
      {"demo --levels 0", "levels must be in 1..8, got 0"},
      {"pareto " + seq + " --pair 0 --lambda-min 10 --lambda-max 1", "got [10, 1]"},
      {"pareto " + seq + " --pair 0 --level 9", "finest level must be in 0..3, got 9"},
      {"sweep --sequences " + seq + " --eps-points -1", "--eps-points: Value -1 not in range 0 to 1000"},
      {"report --sequences " + seq + " --lambda-points 2000000000", "--lambda-points: Value 2000000000 not in range"},
  };
  for (const auto& [command, message] : cases) {
    expect_clear_error(bivo(command + " --output " + q(out)), message);
    EXPECT_FALSE(fs::exists(out)) << command;
  }
}

// profile wrote a row of zeros and exited 0 for a method whose runs failed, and ran the
// warm-up before refusing a frame window.
TEST_F(HardeningCli, ProfileFailuresExitOne) {
  const fs::path out = dir_ / "out";
  const std::string profile = "profile " + q(sequence_) + " --methods single:gn --repetitions 1 ";
  expect_clear_error(bivo(profile + "--max-frames -3 --output " + q(out)), "got -3");
  EXPECT_FALSE(fs::exists(out));
  expect_clear_error(bivo(profile + "--first-frame 100 --output " + q(out)), "1 of 1 unit(s) failed");
  EXPECT_TRUE(fs::exists(out / "profile.md"));  // written, its note saying why
  EXPECT_EQ(bivo(profile + "--first-frame 100 --keep-going --output " + q(dir_ / "kept")).status, 0);
}
