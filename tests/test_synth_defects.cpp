// The renderer's sensor defects (odometry/synth/defects.h) against closed forms on scenes
// whose images are known: a fronto-parallel plane at depth Z in front of a camera looking
// along +z (depth bias, quantization, gain, vignetting, unsynchronized depth), a step edge
// (misregistration shift f b / Z), a textured plane under a known translation (motion blur =
// the average of shifted images; rolling shutter = each row at its own pose).
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <vector>

#include <gtest/gtest.h>

#include "odometry/io/tum_dataset.h"
#include "odometry/io/vignetting.h"
#include "odometry/synth/defects.h"
#include "odometry/synth/exposure.h"
#include "odometry/synth/motion.h"
#include "odometry/synth/render.h"
#include "odometry/synth/scene.h"
#include "odometry/synth/sequence.h"
#include "odometry/synth/stress_set.h"
#include "odometry/synth/texture.h"
#include "solvers/error.h"

namespace synth = bivo::odometry::synth;
namespace io = bivo::odometry::io;

namespace {

constexpr int W = 640, H = 480;

// A plane z = Z (world = camera frame at the identity pose), radiance = albedo (ambient 1).
synth::Scene plane_scene(double Z, bool textured) {
  synth::Scene s;
  s.seed = 5;
  s.textures.push_back(textured ? synth::make_poster_texture(11)
                                : synth::make_uniform_texture(11, {0.6f, 0.6f, 0.6f}, 0.0f));
  s.materials.push_back(synth::Material{"m", {0}, 0.5, 0.5});
  s.panels.push_back(synth::Panel{"plane", {-20, -20, Z}, {40, 0, 0}, {0, 40, 0}, 0});
  s.ambient = 1.0;
  s.diffuse = 0.0;
  return s;
}

synth::RenderSettings clean() {
  synth::RenderSettings r;
  r.sensor_noise = false;
  r.depth.max_range_m = 8.0;
  return r;
}

double depth_m(const synth::RenderedFrame& f, int u, int v) { return f.depth[v * f.width + u] / 5000.0; }

Eigen::Isometry3d translated(const Eigen::Vector3d& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = t;
  return T;
}

}  // namespace

TEST(SynthDefects, RadialBiasOnAPlaneIsTheClosedFormAndGrowsWithDepth) {
  // Oracle: disparity bias delta_d = a f_ir b rho^2 turns depth Z into Z / (1 - a Z rho^2).
  synth::RenderSettings r = clean();
  r.defects.bias_radial = 0.03;
  for (double Z : {1.0, 3.0}) {
    const synth::RenderedFrame f = synth::render_frame(plane_scene(Z, false), Eigen::Isometry3d::Identity(), r, 0);
    double worst = 0;
    for (int v = 0; v < H; v += 7) {
      for (int u = 0; u < W; u += 7) {
        const double rho2 = synth::normalized_radius2(u, v, W, H, r.camera.cx, r.camera.cy);
        worst = std::max(worst, std::fabs(depth_m(f, u, v) - Z / (1 - 0.03 * Z * rho2)));
      }
    }
    EXPECT_LT(worst, 1.01e-4) << "Z = " << Z;  // the PNG's 0.2 mm step
    // At the farthest corner (rho = 1): 3 % at 1 m, 9.9 % at 3 m (relative error grows with Z).
    EXPECT_NEAR(depth_m(f, 0, 0) / Z - 1, 0.03 * Z / (1 - 0.03 * Z), 2e-4);
  }
}

TEST(SynthDefects, LowFrequencyBiasIsSmoothStaticAndOfTheRequestedSize) {
  synth::SensorDefects d;
  d.bias_lowfreq = 0.01;
  const double fb = 569.4 * 0.075;
  const std::vector<float> a = synth::disparity_bias_field(d, 1, W, H, 320, 240, fb);
  EXPECT_EQ(a, synth::disparity_bias_field(d, 1, W, H, 320, 240, fb));  // a fixed pattern of the sensor
  EXPECT_NE(a, synth::disparity_bias_field(d, 2, W, H, 320, 240, fb));
  double sum2 = 0, step = 0;
  for (int v = 0; v < H; ++v) {
    for (int u = 0; u + 1 < W; ++u) {
      sum2 += a[v * W + u] * a[v * W + u];
      step = std::max(step, std::fabs(static_cast<double>(a[v * W + u + 1] - a[v * W + u])));
    }
  }
  const double rms_rel = std::sqrt(sum2 / (W * H)) / fb;  // relative error at 1 m
  EXPECT_GT(rms_rel, 0.005);
  EXPECT_LT(rms_rel, 0.02);
  // Smooth: wavelengths >= 400 px, so a pixel step changes it by <= 2 pi / 400 of the peak.
  EXPECT_LT(step / fb, 0.01 * std::sqrt(2.0 / 6.0) * 6 * 2 * M_PI / 400);
}

TEST(SynthDefects, QuantizationStepGrowsWithZSquared) {
  // Oracle: disparity rounded to 1/8 px: depth levels fb / (n / 8), spaced Z^2 / (8 fb).
  synth::RenderSettings r = clean();
  r.sensor_noise = true;
  r.depth.noise_coeff = 0.0;
  const double fb = r.depth.ir_focal_px * r.depth.baseline_m;
  for (double Z : {1.0, 2.0, 4.0}) {
    const synth::RenderedFrame f = synth::render_frame(plane_scene(Z, false), Eigen::Isometry3d::Identity(), r, 0);
    const double level = fb / (std::round(fb / Z / 0.125) * 0.125);
    EXPECT_NEAR(depth_m(f, 320, 240), level, 1.01e-4);
    // The next level farther: 1/z steps by exactly step / fb, so z steps by ~ z^2 step / fb.
    synth::Scene s = plane_scene(Z, false);
    const double measured = depth_m(f, 320, 240);
    double next = measured;
    for (double dz = 0.0005; next == measured && dz < 0.1; dz += 0.0005) {
      s.panels[0].origin.z() = level + dz;
      next = depth_m(synth::render_frame(s, Eigen::Isometry3d::Identity(), r, 0), 320, 240);
    }
    const double png = 2e-4 / (level * level);  // both levels rounded to 0.1 mm
    EXPECT_NEAR(1 / measured - 1 / next, 0.125 / fb, png) << "Z = " << Z;
    EXPECT_NEAR((next - measured) / (level * level), 0.125 / fb, 0.03 * 0.125 / fb + png) << "Z = " << Z;
  }
}

TEST(SynthDefects, MisregistrationShiftsADepthEdgeByFocalTimesBaselineOverDepth) {
  // A half-plane at Z1 = 1 m (x < 0.3 px) over a background at 3 m: moving the depth camera
  // by b along x moves the edge by -fx b / Z1 pixels; the colour image does not move.
  synth::Scene s = plane_scene(3.0, true);
  const double Z1 = 1.0, fx = 535.4, cx = 320.1;
  const double edge_x = (0.3) * Z1 / fx;  // between pixel centres 320 and 321 (cx = 320.1)
  s.panels.push_back(synth::Panel{"near", {-20, -20, Z1}, {20 + edge_x, 0, 0}, {0, 40, 0}, 0});
  synth::RenderSettings r = clean();
  const auto edge_column = [&](const synth::RenderedFrame& f) {
    for (int u = 1; u < W; ++u) {
      if (f.true_depth[240 * W + u] > 2.0f && f.true_depth[240 * W + u - 1] < 2.0f) return u;
    }
    return -1;
  };
  const synth::RenderedFrame base = synth::render_frame(s, Eigen::Isometry3d::Identity(), r, 0);
  for (int shift : {2, 3}) {
    synth::RenderSettings m = r;
    m.defects.depth_offset_m = Eigen::Vector3d(shift * Z1 / fx, 0, 0);
    const synth::RenderedFrame f = synth::render_timed_frame(
        s, [](double) { return Eigen::Isometry3d::Identity(); }, m, 0);
    EXPECT_EQ(edge_column(f), edge_column(base) - shift);
    EXPECT_EQ(f.rgb, base.rgb);
    // Far from the edge the background depth is unchanged (a plane parallel to the motion).
    EXPECT_NEAR(depth_m(f, 600, 240), 3.0, 1.01e-4);
  }
  EXPECT_GT(edge_column(base), static_cast<int>(cx));
}

TEST(SynthDefects, MotionBlurOfAKnownTranslationIsTheAverageOfShiftedImages) {
  // Camera moving along x at V: the samples at dt = -e/3, 0, e/3 see the plane shifted by
  // -s, 0, +s pixels with s = fx V e / (3 Z) = 2, so blurred(u) = mean of sharp(u - 2, u, u + 2).
  const double Z = 1.5, fx = 535.4, e = 0.012, V = 2.0 * 3 * Z / (fx * e);
  const synth::Scene s = plane_scene(Z, true);
  synth::RenderSettings r = clean();
  r.supersampling = 1;
  const synth::RenderedFrame sharp = synth::render_frame(s, Eigen::Isometry3d::Identity(), r, 0);
  r.defects.exposure_s = e;
  r.defects.blur_samples = 3;
  const synth::RenderedFrame blur = synth::render_timed_frame(
      s,
      [&](double dt) {
        return translated({V * dt, 0, 0});
      },
      r, 0);
  double worst = 0, change = 0;
  for (int v = 20; v < H - 20; v += 3) {
    for (int u = 20; u < W - 20; ++u) {
      for (int c = 0; c < 3; ++c) {
        const auto at = [&](const synth::RenderedFrame& f, int x) {
          return static_cast<double>(f.rgb[3 * (v * W + x) + c]);
        };
        const double mean = (at(sharp, u - 2) + at(sharp, u) + at(sharp, u + 2)) / 3.0;
        worst = std::max(worst, std::fabs(at(blur, u) - mean));
        change = std::max(change, std::fabs(at(blur, u) - at(sharp, u)));
      }
    }
  }
  EXPECT_LE(worst, 1.0);    // rounding of the three sharp images and of the blurred one
  EXPECT_GT(change, 20.0);  // the control: blur does change the poster image
}

TEST(SynthDefects, RollingShutterRowsAreEachRenderedAtTheirOwnTime) {
  // Oracle: row v equals the row of a global-shutter image at the pose of its read-out time.
  const synth::Scene s = plane_scene(1.5, true);
  synth::RenderSettings r = clean();
  r.defects.readout_s = 0.03;
  const auto pose_at = [](double dt) { return translated({1.5 * dt, 0.3 * dt, 0}); };
  const synth::RenderedFrame rs = synth::render_timed_frame(s, pose_at, r, 0);
  for (int v : {0, 100, 333, H - 1}) {
    const double dt = synth::row_sample_times(r.defects, v, H)[0];
    EXPECT_NEAR(dt, ((v + 0.5) / H - 0.5) * 0.03, 1e-15);
    synth::RenderSettings g = clean();
    const synth::RenderedFrame at = synth::render_frame(s, pose_at(dt), g, 0);
    const std::vector<std::uint8_t> row_rs(rs.rgb.begin() + 3 * v * W, rs.rgb.begin() + 3 * (v + 1) * W);
    const std::vector<std::uint8_t> row_gs(at.rgb.begin() + 3 * v * W, at.rgb.begin() + 3 * (v + 1) * W);
    EXPECT_EQ(row_rs, row_gs) << "row " << v;
  }
}

TEST(SynthDefects, UnsynchronizedDepthSeesThePlaneAtItsOwnTime) {
  // Camera approaching the plane at 1 m/s: depth taken delay_k later reads Z - delay_k.
  const double Z = 2.0;
  synth::RenderSettings r = clean();
  r.defects.depth_delay_min_s = 0.0;
  r.defects.depth_delay_max_s = 0.014;
  const auto pose_at = [](double dt) { return translated({0, 0, 1.0 * dt}); };
  for (std::uint64_t k : {0u, 1u, 40u}) {
    const double delay = synth::depth_delay(r.defects, r.noise_seed, k);
    const synth::RenderedFrame f = synth::render_timed_frame(plane_scene(Z, false), pose_at, r, k);
    EXPECT_NEAR(depth_m(f, 320, 240), Z - delay, 1.01e-4) << "frame " << k;
  }
  // The delay drifts within its range by steps of the documented size.
  double lo = 1, hi = 0, step2 = 0, prev = synth::depth_delay(r.defects, r.noise_seed, 0);
  for (std::uint64_t k = 1; k < 400; ++k) {
    const double delay = synth::depth_delay(r.defects, r.noise_seed, k);
    lo = std::min(lo, delay);
    hi = std::max(hi, delay);
    step2 += (delay - prev) * (delay - prev);
    prev = delay;
  }
  EXPECT_GE(lo, 0.0);
  EXPECT_LE(hi, 0.014);
  EXPECT_GT(hi - lo, 0.007);  // it wanders over much of the range
  EXPECT_NEAR(std::sqrt(step2 / 399), r.defects.depth_delay_step_s, 0.3e-3);
}

TEST(SynthDefects, VignettingFollowsItsRadialProfile) {
  synth::RenderSettings r = clean();
  r.defects.vignetting = 0.3;
  const synth::RenderedFrame f = synth::render_frame(plane_scene(2.0, false), Eigen::Isometry3d::Identity(), r, 0);
  double worst = 0;
  for (int v = 0; v < H; v += 5) {
    for (int u = 0; u < W; u += 5) {
      const double expected = 0.6 * 255 * (1 - 0.3 * synth::normalized_radius2(u, v, W, H, r.camera.cx, r.camera.cy));
      worst = std::max(worst, std::fabs(f.rgb[3 * (v * W + u)] - expected));
    }
  }
  EXPECT_LE(worst, 0.51);
  EXPECT_NEAR(f.rgb[0], 0.6 * 255 * 0.7, 0.51);  // (0, 0) is the farthest corner from (320.1, 247.6)
}

// The tracker's flat-field correction (io/vignetting.h) of the fall-off the rendering states:
// the plane's intensity is flat again, to its 8-bit rounding amplified by 1 / (1 - k rho^2).
TEST(SynthDefects, DividingOutTheStatedFallOffFlattensThePlane) {
  synth::RenderSettings r = clean();
  r.defects.vignetting = 0.3;
  const synth::RenderedFrame f = synth::render_frame(plane_scene(2.0, false), Eigen::Isometry3d::Identity(), r, 0);
  io::RgbdImage image;
  image.width = W;
  image.height = H;
  for (int i = 0; i < W * H; ++i) image.intensity.push_back(f.rgb[3 * i]);  // a grey plane: R = G = B
  const io::RgbdImage taken = image;
  const io::Intrinsics K{r.camera.fx, r.camera.fy, r.camera.cx, r.camera.cy};
  io::divide_out_vignetting(image, 0.0, K);
  EXPECT_EQ(image.intensity, taken.intensity);
  io::divide_out_vignetting(image, 0.3, K);
  double worst = 0, worst_taken = 0;
  for (int i = 0; i < W * H; ++i) {
    worst = std::max(worst, std::fabs(image.intensity[i] - 0.6 * 255));
    worst_taken = std::max(worst_taken, std::fabs(taken.intensity[i] - 0.6 * 255));
  }
  EXPECT_LE(worst, 0.51 / 0.7);
  EXPECT_GT(worst_taken, 0.29 * 0.6 * 255);  // the corner's fall-off, 0.3 of the centre's light
  EXPECT_THROW(io::divide_out_vignetting(image, 1.0, K), bivo::Error);
  synth::SensorDefects beyond;
  beyond.vignetting = 0.95;  // a fall-off the tracker could not divide out is not rendered
  EXPECT_THROW(synth::validate(beyond), bivo::Error);
}

TEST(SynthDefects, AutoExposureGainScalesTheImageAndFollowsItsWalk) {
  synth::RenderSettings r = clean();
  r.defects.gain_step = 0.05;
  r.defects.gain_memory = 0.9;
  const synth::Scene s = plane_scene(2.0, false);
  for (std::uint64_t k : {0u, 7u}) {
    const synth::RenderedFrame f = synth::render_frame(s, Eigen::Isometry3d::Identity(), r, k);
    const double g = synth::auto_exposure_gain(r.defects, r.noise_seed, k);
    EXPECT_DOUBLE_EQ(f.exposure_gain, g);
    EXPECT_NEAR(f.rgb[3 * (240 * W + 320)], std::min(255.0, 0.6 * 255 * g), 0.51);
  }
  // AR(1) of the log gain: lag-1 correlation = memory, stationary sd = step / sqrt(1 - m^2).
  std::vector<double> lg;
  for (std::uint64_t k = 0; k < 3000; ++k) lg.push_back(std::log(synth::auto_exposure_gain(r.defects, 9, k)));
  double m = 0, s2 = 0, c1 = 0;
  for (double x : lg) m += x;
  m /= lg.size();
  for (std::size_t k = 0; k < lg.size(); ++k) {
    s2 += (lg[k] - m) * (lg[k] - m);
    if (k) c1 += (lg[k] - m) * (lg[k - 1] - m);
  }
  EXPECT_NEAR(c1 / s2, 0.9, 0.03);
  EXPECT_NEAR(std::sqrt(s2 / lg.size()), 0.05 / std::sqrt(1 - 0.81), 0.025);
}

TEST(SynthDefects, NoDefectMeansTheUntimedRenderer) {
  const synth::Scene s = plane_scene(1.5, true);
  synth::RenderSettings r;  // noise on, no defect
  const Eigen::Isometry3d T = translated({0.01, 0, 0});
  const synth::RenderedFrame a = synth::render_frame(s, T, r, 3);
  const synth::RenderedFrame b = synth::render_timed_frame(
      s, [&](double) { return T; }, r, 3);
  EXPECT_EQ(a.rgb, b.rgb);
  EXPECT_EQ(a.depth, b.depth);
  EXPECT_FALSE(r.defects.any());
}

// Each class switches off its own defect and no other; together they leave the fast
// profile's sensor without any defect (the untimed renderer, above).
TEST(SynthDefects, EachDefectClassSwitchesOffItsOwnDefectOnly) {
  synth::SynthOptions o;
  synth::apply_stress_profile("fast", o);
  const synth::SensorDefects all = o.render.defects;
  ASSERT_TRUE(all.depth_bias() && all.misregistered() && all.unsynchronized() && all.depth_outliers());
  ASSERT_TRUE(all.readout_s > 0 && all.exposure_s > 0 && all.gain_step > 0 && all.vignetting > 0);
  const auto without = [&](const std::string& name) {
    synth::SensorDefects d = all;
    synth::switch_off(d, name);
    return d;
  };
  const synth::SensorDefects rs = without("rolling-shutter"), blur = without("blur");
  EXPECT_EQ(rs.readout_s, 0.0);
  EXPECT_EQ(rs.exposure_s, all.exposure_s);
  EXPECT_EQ(blur.exposure_s, 0.0);
  EXPECT_EQ(blur.readout_s, all.readout_s);
  EXPECT_EQ(without("vignetting").vignetting, 0.0);
  EXPECT_EQ(without("vignetting").gain_step, all.gain_step);
  EXPECT_EQ(without("gain").gain_step, 0.0);
  EXPECT_EQ(without("gain").vignetting, all.vignetting);
  EXPECT_FALSE(without("depth-bias").depth_bias());
  EXPECT_TRUE(without("depth-bias").misregistered());
  EXPECT_FALSE(without("misregistration").misregistered());
  EXPECT_TRUE(without("misregistration").unsynchronized());
  EXPECT_FALSE(without("depth-delay").unsynchronized());
  EXPECT_TRUE(without("depth-delay").depth_bias());
  EXPECT_FALSE(without("outliers").depth_outliers());
  EXPECT_EQ(without("outliers").disparity_offset_step_px, all.disparity_offset_step_px);
  EXPECT_EQ(without("disparity-offset").disparity_offset_step_px, 0.0);
  EXPECT_TRUE(without("disparity-offset").depth_outliers());
  synth::SensorDefects none = all;
  for (const std::string& name : synth::defect_class_names()) synth::switch_off(none, name);
  EXPECT_FALSE(none.any());
  EXPECT_EQ(synth::defect_class_names().size(), 9u);
  try {
    synth::switch_off(none, "shutter");
    ADD_FAILURE() << "an unknown defect class was accepted";
  } catch (const bivo::Error& e) {
    EXPECT_NE(std::string(e.what()).find("unknown sensor defect 'shutter' (one of: rolling-shutter"), std::string::npos)
        << e.what();
  }
}

TEST(SynthDefects, RetimedMotionCoversTheSameMotionInFewerFrames) {
  synth::HandheldMotionOptions h;
  h.duration_s = 6.0;
  const bivo::odometry::io::Trajectory m = synth::generate_handheld_motion(h);
  const auto slow = synth::resample_trajectory(m, 0.0, 41, 30.0, "m");
  const auto fast = synth::resample_trajectory(synth::retime_trajectory(m, 2.0), 0.0, 21, 30.0, "m");
  for (int k = 0; k < 21; ++k) {
    EXPECT_LT((fast[k].T_wc.matrix() - slow[2 * k].T_wc.matrix()).norm(), 1e-9) << k;
    EXPECT_NEAR(fast[k].timestamp - fast[0].timestamp, k / 30.0, 1e-12);
  }
}

TEST(SynthDefects, StressSetCrossesDefectsWithStructureAndTexture) {
  const auto set = synth::stress_set(5);
  ASSERT_EQ(set.size(), 11u);
  int structure = 0, texture = 0, fast = 0;
  for (const auto& s : set) {
    EXPECT_TRUE(s.options.render.defects.depth_bias() && s.options.render.defects.misregistered());
    // Calibrated on real frames: outliers and per-frame offsets in both; deep noise grows as z^3.
    EXPECT_TRUE(s.options.render.defects.depth_outliers());
    EXPECT_GT(s.options.render.defects.disparity_offset_step_px, 0.0);
    EXPECT_EQ(s.options.render.defects.noise_exponent, s.trajectory.empty() ? 2.0 : 3.0);
    EXPECT_EQ(s.options.render.depth.noise_correlation_px, s.trajectory.empty() ? 3.0 : 2.0);
    EXPECT_EQ(s.options.frames, 5);
    structure += s.options.category.structure;
    texture += s.options.category.texture;
    if (s.trajectory.empty()) {
      ++fast;
      // 4 deg and 3 cm per frame at 30 Hz on average, peaks of 6-8 deg and about 5 cm.
      synth::HandheldMotionOptions h = s.options.handheld;
      h.duration_s = 11.0;
      const auto poses = synth::resample_trajectory(synth::generate_handheld_motion(h), 0.0, 300, 30.0, "g");
      const synth::MotionSpeeds v = synth::mean_speeds(poses);
      EXPECT_NEAR(v.angular_rps * 180 / M_PI / 30, 4.0, 0.4);
      EXPECT_NEAR(v.linear_mps / 30, 0.03, 0.003);
      std::vector<double> deg, cm;
      for (std::size_t k = 1; k < poses.size(); ++k) {
        const Eigen::Isometry3d rel = poses[k - 1].T_wc.inverse() * poses[k].T_wc;
        deg.push_back(Eigen::AngleAxisd(rel.linear()).angle() * 180 / M_PI);
        cm.push_back(100 * rel.translation().norm());
      }
      std::sort(deg.begin(), deg.end());
      std::sort(cm.begin(), cm.end());
      EXPECT_GT(deg[deg.size() * 95 / 100], 6.0);
      EXPECT_LT(deg.back(), 12.0);
      EXPECT_GT(cm[cm.size() * 95 / 100], 4.0);
      EXPECT_TRUE(s.options.render.defects.unsynchronized());
      EXPECT_TRUE(s.options.render.defects.timed_colour());
    }
  }
  EXPECT_EQ(structure, 6);  // the crossing's 4 and two extra textured deep views
  EXPECT_EQ(texture, 7);
  EXPECT_EQ(fast, 4);
  synth::SynthOptions o;
  EXPECT_THROW(synth::apply_stress_profile("shallow", o), bivo::Error);
}

TEST(SynthDefects, DeepScenesPutMuchOfTheImageBeyondThreeMetres) {
  // Real fr3/long_office_household: median depth 2.4 m; real fr3 frames 27-65 % beyond 3 m.
  for (const auto& s : synth::stress_set(1)) {
    if (!s.trajectory.empty() && s.options.category.texture) {
      const synth::Scene scene = synth::build_scene(s.options.category, 1, s.options.layout);
      synth::RenderSettings r = s.options.render;
      r.defects = synth::SensorDefects();
      const synth::RenderedFrame f = synth::render_frame(scene, scene.nominal_T_wc, r, 0);
      std::vector<float> z;
      for (std::uint16_t d : f.depth) {
        if (d) z.push_back(d / 5000.0f);
      }
      std::sort(z.begin(), z.end());
      const double beyond = static_cast<double>(z.end() - std::upper_bound(z.begin(), z.end(), 3.0f)) / z.size();
      EXPECT_GT(z[z.size() / 2], 2.0) << s.name;
      EXPECT_GT(beyond, 0.25) << s.name;
      EXPECT_LT(beyond, 0.70) << s.name;
    }
  }
}

TEST(SynthDefects, UnsynchronizedSequenceListsDepthAtItsOwnTimestamps) {
  namespace fs = std::filesystem;
  const fs::path out = fs::temp_directory_path() / ("bivo_test_synth_defects_" + std::to_string(::getpid()));
  fs::remove_all(out);
  synth::SynthOptions o;
  o.category = synth::parse_category("structure_notexture_near");
  o.frames = 3;
  o.threads = 1;
  o.render.defects.depth_delay_min_s = 0.004;
  o.render.defects.depth_delay_max_s = 0.012;
  const std::string dir = synth::render_sequence(o, out.string());
  // The reader associates every colour image with its own depth image, delay_k apart.
  const auto seq = bivo::odometry::io::open_tum_sequence(dir);
  ASSERT_EQ(seq.frames.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_NEAR(seq.frames[k].depth_time - seq.frames[k].rgb_time, synth::depth_delay(o.render.defects, o.seed, k),
                1.01e-6);
  }
  // A delay of half a frame or more would pair the wrong images: refused before any work.
  o.render.defects.depth_delay_max_s = 0.02;
  EXPECT_THROW(synth::render_sequence(o, out.string() + "/late"), bivo::Error);
  EXPECT_FALSE(fs::exists(out / "late"));
  // The stress set fixes its parameters: a rendering flag is refused.
  const std::string cmd = std::string(BIVO_BINARY) + " synth --stress-set --trajectories " + out.string() +
                          " --seed 3 --output " + (out / "s").string() + " 2>/dev/null >/dev/null";
  EXPECT_NE(std::system(cmd.c_str()), 0);
  EXPECT_FALSE(fs::exists(out / "s" / "stress_set.json"));
  fs::remove_all(out);
}
