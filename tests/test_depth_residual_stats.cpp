// `bivo depth-stats`' colour fall-off (experiments/depth_residual_stats.h) against the
// renderer's vignetting, whose value is known: a textureless rendering with a fall-off of
// k = 0.25 at the corner gives k, one without gives 0, and per-frame exposure steps (one gain
// per image) do not move it; a camera that does not move does not observe it ("-"). The depth statistics of the same
// renderings stay those of unbiased depth (mean r/z near 0).
#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <tuple>

#include <gtest/gtest.h>
#include <unistd.h>

#include "experiments/depth_residual_stats.h"
#include "odometry/synth/sequence.h"
#include "solvers/error.h"

using namespace bivo;
namespace fs = std::filesystem;

namespace {

class ColourFalloff : public ::testing::Test {
 protected:
  // ctest runs each test in its own process: each renders only the sequences it reads.
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("bivo_test_depth_stats_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }

  // 14 frames of the textureless near plane, turning at `turn` deg/s (and moving when it
  // turns), with fall-off k and auto-exposure steps of log-gain sigma `gain_step`.
  static std::string render(const std::string& name, double k, double gain_step, double turn = 60.0) {
    odometry::synth::SynthOptions o;
    o.category = odometry::synth::parse_category("nostructure_notexture_near");
    o.frames = 14;
    o.seed = 3;
    o.handheld.mean_angular_speed_dps = turn;
    if (turn == 0.0) o.handheld.mean_linear_speed_mps = 0.0;
    o.render.defects.vignetting = k;
    o.render.defects.gain_step = gain_step;
    o.sequence_name = "rgbd_dataset_freiburg3_" + name;
    return odometry::synth::render_sequence(o, dir_.string());
  }
  // The four sequences the tests read, each rendered at its first use: (k, gain step, turn).
  static const std::string& sequence(const std::string& name) {
    static std::map<std::string, std::string> rendered;
    const auto it = rendered.find(name);
    if (it != rendered.end()) return it->second;
    const std::map<std::string, std::array<double, 3>> settings = {{"vignetted", {0.25, 0.0, 60.0}},
                                                                   {"clean", {0.0, 0.0, 60.0}},
                                                                   {"exposed", {0.25, 0.05, 60.0}},
                                                                   {"still", {0.25, 0.0, 0.0}}};
    const std::array<double, 3>& p = settings.at(name);
    return rendered[name] = render(name, p[0], p[1], p[2]);
  }

  static experiments::DepthResidualStats stats(const std::string& sequence) {
    experiments::DepthResidualOptions o;
    o.gap = 2;
    o.max_pairs = 12;
    return experiments::depth_residual_stats(sequence, o);
  }

  static fs::path dir_;
};
fs::path ColourFalloff::dir_;

}  // namespace

TEST_F(ColourFalloff, RecoversTheRenderedVignetting) {
  const experiments::DepthResidualStats s = stats(sequence("vignetted"));
  EXPECT_EQ(s.pairs, 12);
  EXPECT_NEAR(s.colour_falloff, 0.25, 0.02);
  EXPECT_LT(std::fabs(s.mean_rel), 2e-3);  // unbiased depth
}

TEST_F(ColourFalloff, IsZeroWithoutVignetting) { EXPECT_NEAR(stats(sequence("clean")).colour_falloff, 0.0, 0.02); }

TEST_F(ColourFalloff, ExposureStepsDoNotMoveIt) {
  const double with_steps = stats(sequence("exposed")).colour_falloff;
  EXPECT_NEAR(with_steps, 0.25, 0.02);
  EXPECT_NEAR(with_steps, stats(sequence("vignetted")).colour_falloff, 0.01);
}

TEST_F(ColourFalloff, TheTableShowsIt) {
  const std::string table = experiments::depth_residual_table({stats(sequence("vignetted"))});
  EXPECT_NE(table.find("colour fall-off k"), std::string::npos);
  EXPECT_NE(table.find("| 0.2"), std::string::npos) << table;
}

TEST_F(ColourFalloff, IsNotReportedWhenTheCameraDoesNotMove) {
  const experiments::DepthResidualStats s = stats(sequence("still"));
  EXPECT_EQ(s.pairs, 12);
  EXPECT_TRUE(std::isnan(s.colour_falloff)) << s.colour_falloff;
  const std::string table = experiments::depth_residual_table({s});
  EXPECT_NE(table.find("| - |"), std::string::npos) << table;
}

// --pairs 0 or -1 ran one pair: a count below 1 is refused, naming the value, as is a gap below 1.
TEST_F(ColourFalloff, PairsAndGapBelowOneAreRefused) {
  for (const auto& [gap, pairs, message] :
       {std::tuple{1, 0, "pairs 0"}, std::tuple{1, -1, "pairs -1"}, std::tuple{0, 5, "gap 0"}}) {
    experiments::DepthResidualOptions o;
    o.gap = gap;
    o.max_pairs = pairs;
    try {
      experiments::depth_residual_stats(sequence("clean"), o);
      ADD_FAILURE() << message << " was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  }
  experiments::DepthResidualOptions o;
  o.max_pairs = 3;
  EXPECT_EQ(experiments::depth_residual_stats(sequence("clean"), o).pairs, 3);
}
