// Synthetic sequences as files: frame k back-projected with the written ground truth lands
// on frame k+1 with depth and intensity differences at the noise level (and a wrong pose
// does not); groundtruth.txt holds exactly the poses rendered; same seed -> same bytes;
// bad input -> bivo::Error naming the culprit, and no half-written folder.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "odometry/io/png_io.h"
#include "odometry/io/trajectory.h"
#include "odometry/synth/sequence.h"
#include "solvers/error.h"
#include "solvers/geometry/se3.h"

namespace fs = std::filesystem;
namespace synth = bivo::odometry::synth;
using bivo::odometry::io::Trajectory;

namespace {

fs::path fresh_dir(const std::string& tag) {
  const fs::path p = fs::temp_directory_path() / ("bivo_test_synth_" + tag + "_" + std::to_string(::getpid()));
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

struct Frame {
  bivo::odometry::io::Png8 rgb;
  bivo::odometry::io::Png16 depth;
  double gray(int u, int v) const {
    const std::uint8_t* p = &rgb.data[3 * (v * rgb.width + u)];
    return 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2];
  }
  double z(int u, int v) const { return depth.data[v * depth.width + u] / 5000.0; }
};

std::vector<std::string> list_column(const fs::path& file, int column) {
  std::ifstream in(file);
  std::vector<std::string> out;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    std::string f;
    for (int c = 0; c <= column; ++c) s >> f;
    out.push_back(f);
  }
  return out;
}

struct Medians {
  double depth_m = 0, intensity = 0;
  std::size_t pixels = 0;
};

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// Warps every valid pixel of frame 1 into frame 2 with T_21 and compares the predicted
// depth and gray value with frame 2's, bilinearly interpolated where all four neighbours
// have depth agreeing within 2% (no interpolation across an edge).
Medians warp_residuals(const Frame& f1, const Frame& f2, const Eigen::Isometry3d& T_21, const synth::PinholeCamera& K) {
  std::vector<double> dz, di;
  const int W = f1.rgb.width, H = f1.rgb.height;
  for (int v = 0; v < H; v += 2) {
    for (int u = 0; u < W; u += 2) {
      const double z1 = f1.z(u, v);
      if (z1 <= 0) continue;
      const Eigen::Vector3d p1((u - K.cx) / K.fx * z1, (v - K.cy) / K.fy * z1, z1);
      const Eigen::Vector3d p2 = T_21 * p1;
      const double x = K.fx * p2.x() / p2.z() + K.cx, y = K.fy * p2.y() / p2.z() + K.cy;
      const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
      if (x0 < 0 || y0 < 0 || x0 + 1 >= W || y0 + 1 >= H) continue;
      const double ax = x - x0, ay = y - y0;
      double zs[4] = {f2.z(x0, y0), f2.z(x0 + 1, y0), f2.z(x0, y0 + 1), f2.z(x0 + 1, y0 + 1)};
      const double zmin = *std::min_element(zs, zs + 4), zmax = *std::max_element(zs, zs + 4);
      if (zmin <= 0 || zmax > 1.02 * zmin) continue;
      const auto lerp = [&](double a, double b, double c, double d) {
        return (1 - ay) * ((1 - ax) * a + ax * b) + ay * ((1 - ax) * c + ax * d);
      };
      dz.push_back(std::fabs(lerp(zs[0], zs[1], zs[2], zs[3]) - p2.z()));
      di.push_back(std::fabs(lerp(f2.gray(x0, y0), f2.gray(x0 + 1, y0), f2.gray(x0, y0 + 1), f2.gray(x0 + 1, y0 + 1)) -
                             f1.gray(u, v)));
    }
  }
  return {median(dz), median(di), dz.size()};
}

Frame load(const fs::path& seq, const std::string& rgb_rel, const std::string& depth_rel) {
  return {bivo::odometry::io::read_png8((seq / rgb_rel).string()),
          bivo::odometry::io::read_png16((seq / depth_rel).string())};
}

// Renders `frames` frames and checks every consecutive pair; returns the medians of the
// pair medians with the true and with a perturbed (2 cm sideways and along the optical
// axis, 1 degree of yaw) motion.
void check_back_projection(const synth::SynthOptions& o, const fs::path& seq, Medians* truth, Medians* wrong) {
  const Trajectory gt = bivo::odometry::io::read_tum_trajectory((seq / "groundtruth.txt").string());
  const auto rgbs = list_column(seq / "associations.txt", 1), depths = list_column(seq / "associations.txt", 3);
  ASSERT_EQ(rgbs.size(), gt.size());
  std::vector<double> tz, ti, wz, wi;
  bivo::solvers::se3::Vector6d delta;
  delta << 0.02, 0.0, 0.02, 0.0, 0.0175, 0.0;
  for (std::size_t k = 0; k + 1 < gt.size(); ++k) {
    const Frame f1 = load(seq, rgbs[k], depths[k]), f2 = load(seq, rgbs[k + 1], depths[k + 1]);
    const Eigen::Isometry3d T_21 = gt[k + 1].T_wc.inverse() * gt[k].T_wc;
    const Medians t = warp_residuals(f1, f2, T_21, o.render.camera);
    const Medians w = warp_residuals(f1, f2, bivo::solvers::se3::exp(delta) * T_21, o.render.camera);
    EXPECT_GT(t.pixels, 10000u) << "pair " << k;
    tz.push_back(t.depth_m);
    ti.push_back(t.intensity);
    wz.push_back(w.depth_m);
    wi.push_back(w.intensity);
  }
  *truth = {median(tz), median(ti), 0};
  *wrong = {median(wz), median(wi), 0};
}

}  // namespace

TEST(SynthSequence, BackProjectionWithGroundTruthMatchesAtNoiseLevel) {
  const fs::path out = fresh_dir("backproj");
  for (const char* category : {"structure_texture_near", "nostructure_texture_far", "structure_notexture_near"}) {
    synth::SynthOptions o;
    o.category = synth::parse_category(category);
    o.frames = 4;
    o.seed = 11;
    const fs::path seq = synth::render_sequence(o, out.string());
    Medians truth, wrong;
    check_back_projection(o, seq, &truth, &wrong);
    // Noise level: depth noise sd ~1.7e-3 z^2 per frame (test_synth_render), so the
    // difference of two frames has median |.| ~ 0.67 * sqrt(2) * 1.7e-3 z^2 ~ 1.6 mm z^2;
    // intensity noise sd ~2.4 gray levels per channel, gray difference median ~ 1.6.
    const double z = o.category.distance_m();
    std::cout << category << ": median |dz| = " << truth.depth_m * 1000 << " mm, median |dI| = " << truth.intensity
              << " (wrong pose: " << wrong.depth_m * 1000 << " mm, " << wrong.intensity << ")\n";
    EXPECT_LT(truth.depth_m, 2.5e-3 * z * z) << category;
    EXPECT_LT(truth.intensity, 2.5) << category;
    // The check can fail: a 2 cm + 2 cm / 1 degree error in the motion is clearly visible.
    EXPECT_GT(wrong.depth_m, 2.0 * truth.depth_m) << category;
    if (o.category.texture) {
      EXPECT_GT(wrong.intensity, 2.0 * truth.intensity) << category;
    }
  }
  fs::remove_all(out);
}

TEST(SynthSequence, BackProjectionAlongRealTumTrajectory) {
  const fs::path traj =
      fs::path(BIVO_SHARED_DIR) / "data/trajectories/rgbd_dataset_freiburg3_structure_texture_near-groundtruth.txt";
  if (!fs::exists(traj)) GTEST_SKIP() << "shared data not found at " << traj << " (BIVO_SHARED_DIR)";
  const fs::path out = fresh_dir("real");
  synth::SynthOptions o;
  o.category = synth::parse_category("structure_texture_near");
  o.frames = 4;
  o.seed = 12;
  o.start_offset_s = 10.0;
  const Trajectory motion = bivo::odometry::io::read_tum_trajectory(traj.string());
  const fs::path seq = synth::render_sequence(o, motion, out.string(), traj.string());
  Medians truth, wrong;
  check_back_projection(o, seq, &truth, &wrong);
  std::cout << "real fr3 motion: median |dz| = " << truth.depth_m * 1000 << " mm, median |dI| = " << truth.intensity
            << "\n";
  EXPECT_LT(truth.depth_m, 2.5e-3);
  EXPECT_LT(truth.intensity, 2.5);
  EXPECT_GT(wrong.intensity, 2.0 * truth.intensity);
  fs::remove_all(out);
}

TEST(SynthSequence, GroundTruthFileHoldsThePosesRenderedWithRelativeMotionUnchanged) {
  const fs::path out = fresh_dir("gt");
  synth::SynthOptions o;
  o.category = synth::parse_category("nostructure_notexture", "near");
  o.frames = 5;
  o.seed = 13;
  o.render.supersampling = 1;
  synth::HandheldMotionOptions h;
  h.seed = 99;
  const Trajectory motion = synth::generate_handheld_motion(h);
  const fs::path seq = synth::render_sequence(o, motion, out.string(), "test motion");
  EXPECT_NE(seq.filename().string().find("freiburg3"), std::string::npos);
  const Trajectory gt = bivo::odometry::io::read_tum_trajectory((seq / "groundtruth.txt").string());
  const Trajectory planned = synth::frame_poses(o, synth::build_scene(o.category, o.seed), motion, "test motion");
  ASSERT_EQ(gt.size(), 5u);
  // Oracle for the relative motion: the raw motion interpolated directly (s = 0 at its samples).
  const Trajectory raw = synth::resample_trajectory(motion, 0.0, 5, 30.0, "raw");
  for (std::size_t k = 0; k < gt.size(); ++k) {
    EXPECT_NEAR(gt[k].timestamp, motion.front().timestamp + k / 30.0, 1e-6);
    EXPECT_LT((gt[k].T_wc.matrix() - planned[k].T_wc.matrix()).cwiseAbs().maxCoeff(), 2e-9);
    if (k == 0) continue;
    const Eigen::Isometry3d rel_gt = gt[k - 1].T_wc.inverse() * gt[k].T_wc;
    const Eigen::Isometry3d rel_raw = raw[k - 1].T_wc.inverse() * raw[k].T_wc;
    EXPECT_LT((rel_gt.matrix() - rel_raw.matrix()).cwiseAbs().maxCoeff(), 1e-8);
  }
  // The anchor frame (the middle one) sits exactly at the scene's nominal viewing pose.
  const synth::Scene scene = synth::build_scene(o.category, o.seed);
  EXPECT_LT((gt[2].T_wc.matrix() - scene.nominal_T_wc.matrix()).cwiseAbs().maxCoeff(), 2e-9);
  // Listing files agree with the folders.
  const auto rgbs = list_column(seq / "rgb.txt", 1);
  ASSERT_EQ(rgbs.size(), 5u);
  for (const auto& r : rgbs) EXPECT_TRUE(fs::exists(seq / r)) << r;
  EXPECT_TRUE(fs::exists(seq / "scene.json"));
  EXPECT_TRUE(fs::exists(seq / "depth.txt"));
  fs::remove_all(out);
}

TEST(SynthSequence, SameSeedGivesIdenticalFilesWhateverTheThreadsOtherSeedDoesNot) {
  const fs::path out = fresh_dir("seed");
  synth::SynthOptions o;
  o.category = synth::parse_category("structure_texture_far");
  o.frames = 2;
  o.seed = 21;
  o.threads = 2;
  o.sequence_name = "a_freiburg3";
  const fs::path a = synth::render_sequence(o, out.string());
  o.sequence_name = "b_freiburg3";
  o.threads = 1;  // a: two threads, b: one
  const fs::path b = synth::render_sequence(o, out.string());
  o.sequence_name = "c_freiburg3";
  o.seed = 22;
  const fs::path c = synth::render_sequence(o, out.string());
  const auto bytes = [](const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  int compared = 0;
  for (const auto& e : fs::recursive_directory_iterator(a)) {
    if (!e.is_regular_file()) continue;
    const fs::path rel = fs::relative(e.path(), a);
    if (rel == "scene.json" || rel.string().find(".txt") != std::string::npos) {
      // Text files name the sequence; compare them with the name replaced.
      std::string ta = bytes(e.path()), tb = bytes(b / rel);
      for (auto* t : {&ta, &tb}) {
        for (auto pos = t->find("_freiburg3"); pos != std::string::npos; pos = t->find("_freiburg3", pos + 1))
          (*t)[pos - 1] = 'X';
      }
      EXPECT_EQ(ta, tb) << rel;
    } else {
      EXPECT_EQ(bytes(e.path()), bytes(b / rel)) << rel;
    }
    ++compared;
  }
  EXPECT_EQ(compared, 2 * 2 + 5 + 1);  // two PNGs per frame, five text files, the output marker
  const auto rgb = list_column(a / "rgb.txt", 1);
  EXPECT_NE(bytes(a / rgb[0]), bytes(c / list_column(c / "rgb.txt", 1)[0]));
  fs::remove_all(out);
}

TEST(SynthSequence, BadInputGivesClearErrorsAndNoFolder) {
  const fs::path out = fresh_dir("bad");
  const auto expect_error = [](const auto& f, const std::string& needle) {
    try {
      f();
      ADD_FAILURE() << "no error; expected one mentioning '" << needle << "'";
    } catch (const bivo::Error& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  expect_error([] { synth::parse_category("structure_texture_middle"); }, "structure_texture_middle");
  expect_error([] { synth::parse_category("wood_texture_near"); }, "wood_texture_near");
  expect_error([] { synth::parse_category("structure_texture"); }, "needs a distance");
  expect_error([] { synth::parse_category("structure_texture_near", "far"); }, "contradicts");
  expect_error([] { bivo::odometry::io::read_tum_trajectory("/nonexistent/trajectory.txt"); },
               "/nonexistent/trajectory.txt");

  synth::SynthOptions o;
  o.category = synth::parse_category("structure_texture_near");
  o.frames = 10;
  Trajectory one(1);
  expect_error([&] { synth::render_sequence(o, one, out.string(), "one_pose.txt"); }, "one_pose.txt");
  Trajectory short_motion(3);
  for (int k = 0; k < 3; ++k) short_motion[k].timestamp = 0.01 * k;
  expect_error([&] { synth::render_sequence(o, short_motion, out.string(), "short.txt"); }, "too short");
  Trajectory gappy(4);
  for (int k = 0; k < 4; ++k) gappy[k].timestamp = k < 2 ? 0.01 * k : 1.0 + 0.01 * k;
  o.frames = 3;
  expect_error([&] { synth::render_sequence(o, gappy, out.string(), "gappy.txt"); }, "gap");
  o.sequence_name = "my_sequence";
  expect_error([&] { synth::render_sequence(o, out.string()); }, "freiburg3");
  o.sequence_name = "rgbd_dataset_freiburg1_desk_synth_freiburg3";  // the reader would pick freiburg1
  expect_error([&] { synth::render_sequence(o, out.string()); }, "517.3");
  o.sequence_name.clear();
  o.frames = 0;
  expect_error([&] { synth::render_sequence(o, out.string()); }, "frames");
  EXPECT_TRUE(fs::is_empty(out)) << "a failed render left files in " << out;
  fs::remove_all(out);
}

TEST(SynthSequence, CommandLineContract) {
  const fs::path out = fresh_dir("cli");
  const std::string bin = BIVO_BINARY;
  const std::string ok = bin + " synth --category structure_texture_near --frames 3 --seed 4 --output " + out.string() +
                         " > " + (out / "stdout.txt").string();
  ASSERT_EQ(std::system(ok.c_str()), 0) << ok;
  const fs::path seq = out / "rgbd_dataset_freiburg3_synth_structure_texture_near";
  EXPECT_EQ(list_column(seq / "rgb.txt", 1).size(), 3u);
  EXPECT_EQ(bivo::odometry::io::read_tum_trajectory((seq / "groundtruth.txt").string()).size(), 3u);

  const auto fails_with = [&](const std::string& args, const std::string& needle) {
    const fs::path err = out / "stderr.txt";
    const std::string cmd =
        bin + " synth " + args + " --output " + out.string() + " 2> " + err.string() + " >/dev/null";
    EXPECT_NE(std::system(cmd.c_str()), 0) << cmd;
    std::ifstream in(err);
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    EXPECT_NE(text.find(needle), std::string::npos) << cmd << " -> " << text;
  };
  fails_with("--category pyramid_texture_near --frames 3", "pyramid_texture_near");
  fails_with("--category structure_texture_near --trajectory /nonexistent/gt.txt", "/nonexistent/gt.txt");
  const fs::path tiny = out / "tiny.txt";
  std::ofstream(tiny) << "1.0 0 0 0 0 0 0 1\n1.01 0 0 0 0 0 0 1\n";
  fails_with("--category structure_texture --distance far --frames 30 --trajectory " + tiny.string(), "too short");
  fs::remove_all(out);
}
