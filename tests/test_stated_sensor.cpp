// What a sequence states about its sensor (io/sensor_description.h): a bivo synth rendering's
// scene.json gives the rolling-shutter readout and the colour fall-off it was rendered with;
// the tracker's defaults (readout_time and vignetting -1) track it exactly as if they were
// given, and track a sequence that states none (real TUM data) as a global shutter without a
// fall-off; a malformed statement is an error naming the file and key.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>

#include "odometry/io/sensor_description.h"
#include "odometry/io/tum_dataset.h"
#include "odometry/odometry_methods.h"
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
    fall_off_ = o.render.defects.vignetting;
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }

  static TrackerOptions options(double readout, double vignetting = -1.0) {
    TrackerOptions t;
    t.method = "joint";
    t.finest_level = 1;
    t.readout_time = readout;
    t.vignetting = vignetting;
    return t;
  }

  static void write(const fs::path& file, const std::string& text) { std::ofstream(file) << text; }

  static fs::path dir_;
  static std::string sequence_;
  static double rendered_;  // the readout the frames were rendered with
  static double fall_off_;  // and the vignetting
};
fs::path StatedReadout::dir_;
std::string StatedReadout::sequence_;
double StatedReadout::rendered_ = 0.0;
double StatedReadout::fall_off_ = 0.0;

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
  EXPECT_FALSE(io::open_tum_sequence(copy.string()).vignetting.has_value());
  const TrackResult stated = track_sequence(copy.string(), options(-1.0));
  EXPECT_EQ(stated.readout_time, 0.0);
  EXPECT_EQ(stated.vignetting, 0.0);
  EXPECT_TRUE(same_poses(stated, track_sequence(copy.string(), options(0.0, 0.0))));

  write(copy / "scene.json", R"({"generator": "elsewhere", "sensor_defects": {"bias_radial": 0.01}})");
  EXPECT_FALSE(io::stated_readout_time(copy.string()).has_value());
  EXPECT_FALSE(io::stated_vignetting(copy.string()).has_value());
}

TEST_F(StatedReadout, MalformedStatementIsAnErrorNamingFileAndKey) {
  const fs::path copy = dir_ / "malformed";
  fs::create_directories(copy);
  using Reader = std::optional<double> (*)(const std::string&);
  const auto expect_error = [&](Reader read, const std::string& text, const std::string& needle) {
    write(copy / "scene.json", text);
    try {
      read(copy.string());
      ADD_FAILURE() << "accepted " << text;
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("scene.json"), std::string::npos) << what;
      EXPECT_NE(what.find(needle), std::string::npos) << what;
    }
  };
  const Reader readout = io::stated_readout_time, fall_off = io::stated_vignetting;
  expect_error(readout, R"({"sensor_defects": {"readout_s": 2}})", "readout_s: 2");
  expect_error(readout, R"({"sensor_defects": {"readout_s": -0.01}})", "readout_s: -0.01");
  expect_error(readout, R"({"sensor_defects": {"readout_s": "fast"}})", "readout_s: \"fast\"");
  expect_error(readout, R"({"sensor_defects": )", "scene.json");
  expect_error(fall_off, R"({"sensor_defects": {"vignetting": 1}})", "vignetting: 1");
  expect_error(fall_off, R"({"sensor_defects": {"vignetting": -0.1}})", "vignetting: -0.1");
  expect_error(fall_off, R"({"sensor_defects": {"vignetting": "dark"}})", "vignetting: \"dark\"");
}

// The fall-off is divided out by default: as if given, not as the frames were taken; a pair
// loaded alone gets it too, and joint's brightness model then has no fall-off term of its own.
TEST_F(StatedReadout, FallOffReadAsRenderedAndDividedOutByDefault) {
  const io::TumSequence seq = io::open_tum_sequence(sequence_);
  ASSERT_TRUE(seq.vignetting.has_value());
  ASSERT_GT(fall_off_, 0.0);
  EXPECT_EQ(*seq.vignetting, fall_off_);
  EXPECT_EQ(std::count(seq.list_files.begin(), seq.list_files.end(), io::sensor_description_path(sequence_)), 1);

  const TrackResult stated = track_sequence(sequence_, options(-1.0));
  const TrackResult given = track_sequence(sequence_, options(-1.0, fall_off_));
  const TrackResult taken = track_sequence(sequence_, options(-1.0, 0.0));
  EXPECT_EQ(stated.vignetting, fall_off_);
  EXPECT_EQ(taken.vignetting, 0.0);
  EXPECT_TRUE(same_poses(stated, given));
  EXPECT_FALSE(same_poses(stated, taken));

  // The pair's frames as the tracker loads them: the fall-off divided out of the taken ones.
  const FramePair divided = load_frame_pair(sequence_, 2, 3, options(-1.0));
  const FramePair as_taken = load_frame_pair(sequence_, 2, 3, options(-1.0, 0.0));
  EXPECT_EQ(divided.vignetting, fall_off_);
  EXPECT_EQ(as_taken.vignetting, 0.0);
  const ImageF& d = divided.reference.pyramid.levels[0].intensity;
  const ImageF& t = as_taken.reference.pyramid.levels[0].intensity;
  // rho^2 by hand: (0, 0) is the corner farthest from the principal point (cx, cy).
  const double cx = seq.intrinsics.cx, cy = seq.intrinsics.cy;
  const double rho2_centre = ((320 - cx) * (320 - cx) + (248 - cy) * (248 - cy)) / (cx * cx + cy * cy);
  EXPECT_NEAR(d.at(0, 0) / t.at(0, 0), 1.0 / (1.0 - fall_off_), 1e-5);  // (0, 0): the farthest corner
  EXPECT_NEAR(d.at(320, 248) / t.at(320, 248), 1.0 / (1.0 - fall_off_ * rho2_centre), 1e-5);
  EXPECT_EQ(divided.problem(1, options(-1.0))->options().affine_brightness, 1);
  EXPECT_EQ(as_taken.problem(1, options(-1.0))->options().affine_brightness, 2);

  // Estimated alone (as bivo pareto marks the methods), the pair is the tracker's pair 2 -> 3
  // only with the options as loaded: joint's model follows the frames' divided fall-off.
  TrackerOptions window = options(0.0);
  window.first_frame = 2;
  window.max_frames = 2;
  const TrackResult tracked = track_sequence(sequence_, window);
  ASSERT_EQ(tracked.pairs.size(), 1u);
  const auto alone = [&](const TrackerOptions& o) {
    return estimate_motion(divided.reference, divided.current, Eigen::Isometry3d::Identity(), o).T_21.matrix();
  };
  EXPECT_EQ(alone(divided.as_loaded(options(0.0))), tracked.pairs[0].T_21.matrix());
  EXPECT_NE(alone(options(0.0)), tracked.pairs[0].T_21.matrix());  // -1 read as no fall-off: model 2
}

TEST(StatedSensorOption, MinusOneIsTheSequencesOtherNegativesAreRefused) {
  TrackerOptions o;
  EXPECT_EQ(o.readout_time, -1.0);
  EXPECT_EQ(o.vignetting, -1.0);
  EXPECT_NO_THROW(validate(o));
  EXPECT_EQ(with_stated_sensor(o, 0.03, 0.1).readout_time, 0.03);
  EXPECT_EQ(with_stated_sensor(o, 0.03, 0.1).vignetting, 0.1);
  EXPECT_EQ(with_stated_sensor(o, std::nullopt, std::nullopt).readout_time, 0.0);
  EXPECT_EQ(with_stated_sensor(o, std::nullopt, std::nullopt).vignetting, 0.0);
  o.readout_time = 0.01;  // given: the statement does not replace it
  o.vignetting = 0.2;
  EXPECT_EQ(with_stated_sensor(o, 0.03, 0.1).readout_time, 0.01);
  EXPECT_EQ(with_stated_sensor(o, 0.03, 0.1).vignetting, 0.2);
  o.readout_time = 0.0;
  o.vignetting = 0.0;
  EXPECT_EQ(with_stated_sensor(o, 0.03, 0.1).readout_time, 0.0);
  EXPECT_EQ(with_stated_sensor(o, 0.03, 0.1).vignetting, 0.0);
  for (const double bad : {-0.5, 1.0, 2.0}) {
    o.vignetting = bad;
    EXPECT_THROW(validate(o), Error) << bad;
  }
  // joint fits no fall-off of its own on frames with it divided out; a request stands.
  for (const std::string& m : method_names()) {
    const Method method = parse_method(m);
    EXPECT_EQ(method_affine_brightness(method, -1, true),
              method == Method::kJoint ? 1 : method_affine_brightness(method, -1, false))
        << m;
    EXPECT_EQ(method_affine_brightness(method, 2, true), 2) << m;
  }
}
