// The readout a sequence states (io/sensor_description.h): a bivo synth rendering's scene.json
// gives the readout it was rendered with; the tracker's default (readout_time -1) tracks it
// exactly as if the readout were given, and tracks a sequence that states none (real TUM
// data) as a global shutter; a malformed statement is an error naming the file and key.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>

#include "odometry/io/sensor_description.h"
#include "odometry/io/tum_dataset.h"
#include "odometry/synth/sequence.h"
#include "odometry/synth/stress_set.h"
#include "odometry/tracker.h"
#include "solvers/error.h"

using namespace bivo;
using namespace bivo::odometry;
namespace fs = std::filesystem;

namespace {

class StatedReadout : public ::testing::Test {
 protected:
  // Six frames of the fast stress profile (25 ms readout, unsynchronized depth), rendered once.
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("bivo_test_stated_readout_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    synth::SynthOptions o;
    o.category = synth::parse_category("structure_texture_near");
    synth::apply_stress_profile("fast", o);
    o.frames = 6;
    o.seed = 5;
    o.sequence_name = "rgbd_dataset_freiburg3_stated_readout";
    sequence_ = synth::render_sequence(o, dir_.string());
    rendered_ = o.render.defects.readout_s;
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }

  static TrackerOptions options(double readout) {
    TrackerOptions t;
    t.method = "joint";
    t.finest_level = 1;
    t.readout_time = readout;
    return t;
  }

  static void write(const fs::path& file, const std::string& text) { std::ofstream(file) << text; }

  static fs::path dir_;
  static std::string sequence_;
  static double rendered_;  // the readout the frames were rendered with
};
fs::path StatedReadout::dir_;
std::string StatedReadout::sequence_;
double StatedReadout::rendered_ = 0.0;

bool same_poses(const TrackResult& a, const TrackResult& b) {
  if (a.trajectory.size() != b.trajectory.size()) return false;
  for (std::size_t k = 0; k < a.trajectory.size(); ++k) {
    if (a.trajectory[k].T_wc.matrix() != b.trajectory[k].T_wc.matrix()) return false;
  }
  return true;
}

}  // namespace

TEST_F(StatedReadout, ReadAsRenderedAndUsedByDefault) {
  const io::TumSequence seq = io::open_tum_sequence(sequence_);
  ASSERT_TRUE(seq.readout_time.has_value());
  ASSERT_GT(rendered_, 0.0);
  EXPECT_EQ(*seq.readout_time, rendered_);
  EXPECT_EQ(seq.list_files.back(), io::sensor_description_path(sequence_));

  const TrackResult stated = track_sequence(sequence_, options(-1.0));
  const TrackResult given = track_sequence(sequence_, options(rendered_));
  const TrackResult global = track_sequence(sequence_, options(0.0));
  EXPECT_EQ(stated.readout_time, rendered_);
  EXPECT_EQ(global.readout_time, 0.0);
  EXPECT_TRUE(same_poses(stated, given));
  EXPECT_FALSE(same_poses(stated, global));  // the readout changes the estimates
}

TEST_F(StatedReadout, NoneWithoutADescription) {
  const fs::path copy = dir_ / "without";
  fs::remove_all(copy);
  fs::copy(sequence_, copy, fs::copy_options::recursive);
  fs::remove(copy / "scene.json");
  EXPECT_FALSE(io::open_tum_sequence(copy.string()).readout_time.has_value());
  const TrackResult stated = track_sequence(copy.string(), options(-1.0));
  EXPECT_EQ(stated.readout_time, 0.0);
  EXPECT_TRUE(same_poses(stated, track_sequence(copy.string(), options(0.0))));

  write(copy / "scene.json", R"({"generator": "elsewhere", "sensor_defects": {"bias_radial": 0.01}})");
  EXPECT_FALSE(io::stated_readout_time(copy.string()).has_value());
}

TEST_F(StatedReadout, MalformedStatementIsAnErrorNamingFileAndKey) {
  const fs::path copy = dir_ / "malformed";
  fs::create_directories(copy);
  const auto expect_error = [&](const std::string& text, const std::string& needle) {
    write(copy / "scene.json", text);
    try {
      io::stated_readout_time(copy.string());
      ADD_FAILURE() << "accepted " << text;
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("scene.json"), std::string::npos) << what;
      EXPECT_NE(what.find(needle), std::string::npos) << what;
    }
  };
  expect_error(R"({"sensor_defects": {"readout_s": 2}})", "readout_s: 2");
  expect_error(R"({"sensor_defects": {"readout_s": -0.01}})", "readout_s: -0.01");
  expect_error(R"({"sensor_defects": {"readout_s": "fast"}})", "readout_s: \"fast\"");
  expect_error(R"({"sensor_defects": )", "scene.json");
}

TEST(StatedReadoutOption, MinusOneIsTheSequencesOtherNegativesAreRefused) {
  TrackerOptions o;
  EXPECT_EQ(o.readout_time, -1.0);
  EXPECT_NO_THROW(validate(o));
  EXPECT_EQ(with_stated_readout(o, 0.03).readout_time, 0.03);
  EXPECT_EQ(with_stated_readout(o, std::nullopt).readout_time, 0.0);
  o.readout_time = 0.01;  // given: the statement does not replace it
  EXPECT_EQ(with_stated_readout(o, 0.03).readout_time, 0.01);
  o.readout_time = 0.0;
  EXPECT_EQ(with_stated_readout(o, 0.03).readout_time, 0.0);
}
