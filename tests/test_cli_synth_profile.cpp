// `bivo synth --stress-profile` through the built binary: the profile fixes the sensor, the
// scene's layout flags place its scene (docs/synthetic.md, "Stress set"). Oracles: the nominal
// camera's distance and pitch and the wall's position read back from scene.json against the
// values given; the sensor's defects against the profile's own rendering.
#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "tests/support/cli_suite.h"

namespace fs = std::filesystem;
using bivo::testing::BivoRun;
using bivo::testing::expect_clear_error;
using json = nlohmann::json;

namespace {

const char kDeep[] = "synth --category structure_texture_far --stress-profile deep --frames 2 --threads 1";

class SynthProfile : public ::testing::Test {
 protected:
  SynthProfile() : tmp_("bivo_synth_profile_" + name()) {}
  static std::string name() { return ::testing::UnitTest::GetInstance()->current_test_info()->name(); }
  std::string out(const std::string& folder) const { return " --output '" + tmp_.path.string() + "' --name " + folder; }
  BivoRun bivo(const std::string& args) const { return bivo::testing::run_bivo_in(args, tmp_.path.string()); }
  json scene(const std::string& folder) const {
    std::ifstream in(tmp_.path / folder / "scene.json");
    return json::parse(in);
  }
  bivo::testing::TempDir tmp_;
};

Eigen::Vector3d vec(const json& v) { return {v[0].get<double>(), v[1].get<double>(), v[2].get<double>()}; }

// The nominal camera's centre and optical axis (its rotation's third column).
void nominal_view(const json& scene, Eigen::Vector3d& eye, Eigen::Vector3d& axis) {
  const json& T = scene["scene"]["nominal_T_wc"];
  eye = vec(T["t_xyz"]);
  const Eigen::Quaterniond q(T["q_xyzw"][3].get<double>(), T["q_xyzw"][0].get<double>(), T["q_xyzw"][1].get<double>(),
                             T["q_xyzw"][2].get<double>());
  axis = q.toRotationMatrix().col(2);
}

double wall_y(const json& scene) {
  for (const json& p : scene["scene"]["panels"]) {
    if (p["name"] == "wall") return p["corners"][0][1].get<double>();
  }
  return std::nan("");
}

}  // namespace

TEST_F(SynthProfile, LayoutFlagsPlaceTheProfilesSensorInAnotherScene) {
  const BivoRun own = bivo(kDeep + out("own_freiburg3"));
  ASSERT_EQ(own.status, 0) << own.err;
  const BivoRun placed = bivo(kDeep + out("placed_freiburg3") + " --view-distance 2.6 --view-pitch 22 --wall-behind 2");
  ASSERT_EQ(placed.status, 0) << placed.err;
  const json a = scene("own_freiburg3"), b = scene("placed_freiburg3");

  // The profile's scene: wall 3.5 m behind the zig-zag's back folds (0.4 m), pitch 12 deg.
  Eigen::Vector3d eye, axis;
  nominal_view(a, eye, axis);
  EXPECT_NEAR(wall_y(a), 0.4 + 3.5, 1e-12);
  EXPECT_NEAR(std::asin(-axis.z()) * 180.0 / M_PI, 12.0, 1e-9);
  // The placed one: the values given.
  nominal_view(b, eye, axis);
  EXPECT_NEAR(wall_y(b), 0.4 + 2.0, 1e-12);
  EXPECT_NEAR(std::asin(-axis.z()) * 180.0 / M_PI, 22.0, 1e-9);
  EXPECT_NEAR((vec(b["scene"]["target"]) - eye).norm(), 2.6, 1e-9);
  EXPECT_NEAR(b["scene"]["layout"]["distance_m"].get<double>(), 2.6, 0.0);
  // The same sensor.
  ASSERT_TRUE(a.contains("sensor_defects"));
  EXPECT_EQ(a["sensor_defects"], b["sensor_defects"]);
  EXPECT_EQ(a["depth_sensor"], b["depth_sensor"]);
  EXPECT_EQ(a["intensity_sensor"], b["intensity_sensor"]);
}

TEST_F(SynthProfile, SensorFlagsAreRefusedBesideAProfile) {
  expect_clear_error(bivo(kDeep + out("n_freiburg3") + " --depth-noise 1e-3"),
                     "--stress-profile fixes the sensor; drop --depth-noise");
  EXPECT_FALSE(fs::exists(tmp_.path / "n_freiburg3"));
}

TEST_F(SynthProfile, WithoutSwitchesOffTheNamedDefectsOfTheProfile) {
  const BivoRun own = bivo(kDeep + out("own_freiburg3"));
  ASSERT_EQ(own.status, 0) << own.err;
  const BivoRun less = bivo(kDeep + out("less_freiburg3") + " --without vignetting,depth-bias");
  ASSERT_EQ(less.status, 0) << less.err;
  json a = scene("own_freiburg3")["sensor_defects"], b = scene("less_freiburg3")["sensor_defects"];
  EXPECT_GT(a["bias_radial"].get<double>(), 0.0);
  EXPECT_GT(a["gain_step"].get<double>(), 0.0);
  EXPECT_EQ(b["vignetting"].get<double>(), 0.0);
  EXPECT_EQ(b["bias_radial"].get<double>(), 0.0);
  EXPECT_EQ(b["bias_lowfreq"].get<double>(), 0.0);
  // Every other defect as the profile's.
  for (const char* key : {"vignetting", "bias_radial", "bias_lowfreq"}) a.erase(key), b.erase(key);
  EXPECT_EQ(a, b);
}

TEST_F(SynthProfile, WithoutIsRefusedWithoutAProfileOrWithAnUnknownDefect) {
  expect_clear_error(
      bivo("synth --category structure_texture_far --frames 2 --threads 1" + out("w_freiburg3") + " --without gain"),
      "--without needs --stress-profile");
  expect_clear_error(bivo(kDeep + out("u_freiburg3") + " --without shutter"), "unknown sensor defect 'shutter'");
  EXPECT_FALSE(fs::exists(tmp_.path / "w_freiburg3"));
  EXPECT_FALSE(fs::exists(tmp_.path / "u_freiburg3"));
}
