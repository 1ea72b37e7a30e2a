// Synthetic renderer against independent oracles: plane depth in closed form, the sensor
// noise statistics against the documented model, mip filtering against box averages,
// category contrasts (paper's complexity metrics pi(I), pi(D)), missing-depth rules.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/SVD>

#include "odometry/synth/noise_field.h"
#include "odometry/synth/random.h"
#include "odometry/synth/render.h"
#include "odometry/synth/scene.h"
#include "odometry/synth/texture.h"
#include "solvers/error.h"

namespace synth = bivo::odometry::synth;

namespace {

synth::RenderSettings noiseless() {
  synth::RenderSettings s;
  s.sensor_noise = false;
  return s;
}

std::vector<double> gray(const synth::RenderedFrame& f) {
  std::vector<double> g(static_cast<std::size_t>(f.width) * f.height);
  for (std::size_t i = 0; i < g.size(); ++i) {
    g[i] = 0.299 * f.rgb[3 * i] + 0.587 * f.rgb[3 * i + 1] + 0.114 * f.rgb[3 * i + 2];
  }
  return g;
}

// The paper's complexity metric (eqs. `image complexity metric`, `depth complexity metric`).
template <class Get>
double complexity(int w, int h, Get get) {
  double sum = 0;
  for (int v = 1; v + 1 < h; ++v) {
    for (int u = 1; u + 1 < w; ++u)
      sum += std::fabs(get(u, v + 1) - get(u, v - 1)) + std::fabs(get(u + 1, v) - get(u - 1, v));
  }
  return sum / ((w - 2.0) * (h - 2.0));
}

double stddev(const std::vector<double>& x) {
  double m = 0, s = 0;
  for (double v : x) m += v;
  m /= x.size();
  for (double v : x) s += (v - m) * (v - m);
  return std::sqrt(s / (x.size() - 1));
}

}  // namespace

TEST(SynthRender, PlaneDepthEqualsClosedFormRayPlaneIntersection) {
  // Oracle: in the world frame the plane is z = 0; the pixel ray from camera centre C with
  // direction R K^-1 [u v 1] meets it at t = -C_z / d_z, and t is the depth (d has unit
  // camera-z component).
  const synth::Scene scene = synth::build_scene(synth::parse_category("nostructure_texture_near"), 3);
  ASSERT_EQ(scene.panels.size(), 1u);
  const synth::RenderSettings s = noiseless();
  const synth::RenderedFrame f = synth::render_frame(scene, scene.nominal_T_wc, s, 0);
  const Eigen::Matrix3d R = scene.nominal_T_wc.linear();
  const Eigen::Vector3d C = scene.nominal_T_wc.translation();
  int checked = 0;
  double worst = 0;
  for (int v = 0; v < f.height; ++v) {
    for (int u = 0; u < f.width; ++u) {
      const std::uint16_t d = f.depth[v * f.width + u];
      if (d == 0) continue;
      const Eigen::Vector3d dir =
          R * Eigen::Vector3d((u - s.camera.cx) / s.camera.fx, (v - s.camera.cy) / s.camera.fy, 1);
      const double z = -C.z() / dir.z();
      worst = std::max(worst, std::fabs(d / 5000.0 - z));
      ++checked;
    }
  }
  EXPECT_GT(checked, 0.95 * f.width * f.height);  // the plane fills the view, all in range
  EXPECT_LE(worst, 0.5 / 5000.0 + 1e-9);          // only the PNG's 0.2 mm quantization
}

TEST(SynthRender, NominalViewIsAtTheCategoryDistance) {
  for (const auto& c : synth::all_categories()) {
    const synth::Scene scene = synth::build_scene(c, 1);
    const synth::RenderedFrame f = synth::render_frame(scene, scene.nominal_T_wc, noiseless(), 0);
    const float centre = f.true_depth[240 * 640 + 320];
    EXPECT_NEAR(centre, c.distance_m(), 0.1 * c.distance_m()) << c.name();
    EXPECT_GT(f.valid_depth_fraction, 0.6) << c.name();
  }
}

TEST(SynthRender, DepthNoiseMatchesKinectModel) {
  // Noisy minus true depth, normalized by z^2, against the model: Gaussian c z^2 plus the
  // uniform disparity quantization error of variance (z^2 step / (fx b))^2 / 12.
  const synth::Scene scene = synth::build_scene(synth::parse_category("nostructure_notexture_near"), 4);
  for (double step : {0.0, 0.125}) {
    synth::RenderSettings s;
    s.depth.disparity_step_px = step;
    const synth::RenderedFrame f = synth::render_frame(scene, scene.nominal_T_wc, s, 2);
    std::vector<double> r;
    for (std::size_t i = 0; i < f.depth.size(); ++i) {
      if (f.depth[i] == 0) continue;
      const double z = f.true_depth[i];
      r.push_back((f.depth[i] / 5000.0 - z) / (z * z));
    }
    const double q = step / (s.depth.ir_focal_px * s.depth.baseline_m);
    const double expected = std::sqrt(s.depth.noise_coeff * s.depth.noise_coeff + q * q / 12.0);
    std::cout << "disparity step " << step << " px: sd((z_noisy - z)/z^2) = " << stddev(r) << " (model " << expected
              << ")\n";
    EXPECT_NEAR(stddev(r), expected, 0.05 * expected) << "disparity step " << step;
  }
}

TEST(SynthRender, IntensityNoiseMatchesSensorModel) {
  const synth::Scene scene = synth::build_scene(synth::parse_category("structure_texture_near"), 5);
  synth::RenderSettings s;
  const synth::RenderedFrame noisy = synth::render_frame(scene, scene.nominal_T_wc, s, 1);
  const synth::RenderedFrame clean = synth::render_frame(scene, scene.nominal_T_wc, noiseless(), 1);
  std::vector<double> z;
  for (std::size_t i = 0; i < noisy.rgb.size(); ++i) {
    const double c = clean.rgb[i];
    if (c < 10 || c > 245) continue;  // away from saturation
    // Both images are rounded to integers: add the variance of two rounding errors, 2/12.
    const double var = s.intensity.read_noise * s.intensity.read_noise + s.intensity.shot_noise_gain * c + 2.0 / 12.0;
    z.push_back((noisy.rgb[i] - c) / std::sqrt(var));
  }
  ASSERT_GT(z.size(), 100000u);
  std::cout << "normalized intensity noise sd = " << stddev(z) << " (model 1)\n";
  EXPECT_NEAR(stddev(z), 1.0, 0.05);
}

TEST(SynthRender, CategoriesDifferInTextureAndStructureAsNamed) {
  // Texture: the paper's pi(I) (eq. `image complexity metric`) on noise-free renderings;
  // "notexture" is near-uniform but, like real white foil, not perfectly: a plane of it
  // gives pi(I) ~ 0.26 gray levels (the lamp's smooth shading), the zig-zag ~ 0.76 (plus the
  // shading steps at its folds and the floor line), texture ~ 21-24.
  // Structure: RMS distance of the back-projected points to their least-squares plane;
  // "nostructure" is one plane (zero up to float rounding), "structure" is not.
  double pi_i[2][2], plane_rms[2][2];
  for (bool structure : {false, true}) {
    for (bool texture : {false, true}) {
      synth::SynthCategory c;
      c.structure = structure;
      c.texture = texture;
      const synth::Scene scene = synth::build_scene(c, 6);
      const synth::RenderSettings s = noiseless();
      const synth::RenderedFrame f = synth::render_frame(scene, scene.nominal_T_wc, s, 0);
      const std::vector<double> g = gray(f);
      pi_i[structure][texture] = complexity(f.width, f.height, [&](int u, int v) { return g[v * f.width + u]; });
      std::vector<Eigen::Vector3d> pts;
      for (int v = 0; v < f.height; v += 4) {
        for (int u = 0; u < f.width; u += 4) {
          const double z = f.true_depth[v * f.width + u];
          if (z > 0) pts.emplace_back((u - s.camera.cx) / s.camera.fx * z, (v - s.camera.cy) / s.camera.fy * z, z);
        }
      }
      Eigen::MatrixXd A(pts.size(), 3);
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (const auto& p : pts) mean += p / pts.size();
      for (std::size_t k = 0; k < pts.size(); ++k) A.row(k) = (pts[k] - mean).transpose();
      Eigen::JacobiSVD<Eigen::MatrixXd> svd(A);
      plane_rms[structure][texture] = svd.singularValues()(2) / std::sqrt(double(pts.size()));
    }
  }
  for (bool st : {false, true}) {
    EXPECT_LT(pi_i[st][false], 2.5) << "notexture, structure=" << st;
    EXPECT_GT(pi_i[st][false], 0.1) << "notexture must keep its faint shading, structure=" << st;
    EXPECT_GT(pi_i[st][true], 8.0 * pi_i[st][false]) << "structure=" << st;
    EXPECT_LT(plane_rms[false][st], 1e-5) << "nostructure, texture=" << st;
    EXPECT_GT(plane_rms[true][st], 0.05) << "structure, texture=" << st;
  }
  std::cout << "pi(I) nostructure/structure x notexture/texture: " << pi_i[0][0] << " " << pi_i[0][1] << " "
            << pi_i[1][0] << " " << pi_i[1][1] << "; plane-fit RMS [m]: " << plane_rms[0][0] << " " << plane_rms[1][0]
            << "\n";
}

TEST(SynthRender, DepthIsMissingAtOccludingEdgesGrazingAnglesAndBeyondRange) {
  const synth::Scene scene = synth::build_scene(synth::parse_category("structure_texture_far"), 7);
  synth::RenderSettings s = noiseless();
  s.depth.max_range_m = 2.6;  // the wall behind the zig-zag (~3 m) is then out of range
  const synth::RenderedFrame f = synth::render_frame(scene, scene.nominal_T_wc, s, 0);
  const int W = f.width, H = f.height;
  int jumps = 0, beyond = 0;
  for (int v = 1; v + 1 < H; ++v) {
    for (int u = 1; u + 1 < W; ++u) {
      const int i = v * W + u;
      const float z = f.true_depth[i];
      for (int j : {i + 1, i + W}) {
        const float zn = f.true_depth[j];
        if (z > 0 && zn > 0 && std::fabs(z - zn) > 0.1 * std::min(z, zn)) {
          ++jumps;
          EXPECT_EQ(f.depth[i], 0);
          EXPECT_EQ(f.depth[j], 0);
        }
      }
      if (z > 2.6) {
        ++beyond;
        EXPECT_EQ(f.depth[i], 0);
      }
    }
  }
  EXPECT_GT(jumps, 100);  // the top edge of the zig-zag against the wall is in view
  EXPECT_GT(beyond, 1000);
  // Grazing: a camera looking along the plane sees it at > 75 degrees incidence everywhere.
  const synth::Scene plane = synth::build_scene(synth::parse_category("nostructure_texture_near"), 7);
  const Eigen::Isometry3d grazing = synth::look_at({0, -2, 0.3}, {0, 2, 0.0});
  const synth::RenderedFrame g = synth::render_frame(plane, grazing, noiseless(), 0);
  int hits = 0;
  for (std::size_t i = 0; i < g.depth.size(); ++i) {
    const double z = g.true_depth[i];
    if (z <= 0 || z > 4) continue;
    // Incidence from the ray and the plane normal (0,0,1) in world coordinates.
    const int u = static_cast<int>(i % 640), v = static_cast<int>(i / 640);
    const Eigen::Vector3d d =
        (grazing.linear() * Eigen::Vector3d((u - 320.1) / 535.4, (v - 247.6) / 539.2, 1)).normalized();
    if (std::fabs(d.z()) < std::cos(75.5 * M_PI / 180)) {
      ++hits;
      EXPECT_EQ(g.depth[i], 0);
    }
  }
  EXPECT_GT(hits, 1000);
}

TEST(SynthRender, SameFrameIndexRepeatsAndOtherIndexChangesNoise) {
  const synth::Scene scene = synth::build_scene(synth::parse_category("structure_notexture_near"), 8);
  const synth::RenderSettings s;
  const auto a = synth::render_frame(scene, scene.nominal_T_wc, s, 3);
  const auto b = synth::render_frame(scene, scene.nominal_T_wc, s, 3);
  const auto c = synth::render_frame(scene, scene.nominal_T_wc, s, 4);
  EXPECT_EQ(a.rgb, b.rgb);
  EXPECT_EQ(a.depth, b.depth);
  EXPECT_NE(a.rgb, c.rgb);
  EXPECT_NE(a.depth, c.depth);
}

TEST(SynthTexture, MipLevelsAreBoxAverages) {
  // A one-texel checkerboard of 0 and 1: every texel of level 1 averages to exactly 0.5,
  // and the coarsest level is the mean.
  const int n = 16;
  std::vector<Eigen::Vector3f> t(n * n);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) t[y * n + x] = Eigen::Vector3f::Constant(float((x + y) % 2));
  const synth::MipTexture tex(n, n, t);
  EXPECT_EQ(tex.levels(), 5);
  EXPECT_NEAR(tex.sample(0.37f, 0.61f, 2.0f).x(), 0.5f, 1e-6f);
  EXPECT_NEAR(tex.sample(0.9f, 0.1f, 100.0f).x(), 0.5f, 1e-6f);
  // At level 0, a texel centre returns the texel itself.
  EXPECT_NEAR(tex.sample((3 + 0.5f) / n, (4 + 0.5f) / n, 1.0f).x(), 1.0f, 1e-6f);
  EXPECT_NEAR(tex.sample((4 + 0.5f) / n, (4 + 0.5f) / n, 1.0f).x(), 0.0f, 1e-6f);
  EXPECT_THROW(synth::MipTexture(12, 16, std::vector<Eigen::Vector3f>(12 * 16)), bivo::Error);
}

TEST(SynthRender, CorrelatedDepthNoiseHasUnitVarianceAndGaussianCorrelation) {
  // Oracle: white noise blurred by a Gaussian of sd s has correlation exp(-d^2 / (4 s^2))
  // at distance d; the padding keeps unit variance up to the borders.
  const double s = 2.0;
  const int W = 160, H = 120;
  double lag[3] = {0, 0, 0}, var = 0, corner_var = 0;
  const int fields = 40;
  int n = 0;
  for (int k = 0; k < fields; ++k) {
    const std::vector<float> f = synth::correlated_normal_field(synth::hash3(9, 0xD0, k), W, H, s);
    corner_var += f[0] * f[0] + f[W - 1] * f[W - 1] + f[(H - 1) * W] * f[(H - 1) * W];
    for (int v = 0; v < H; ++v) {
      for (int u = 0; u + 4 < W; ++u) {
        const float a = f[v * W + u];
        var += a * a;
        lag[0] += a * f[v * W + u + 1];
        lag[1] += a * f[v * W + u + 2];
        lag[2] += a * f[v * W + u + 4];
        ++n;
      }
    }
  }
  EXPECT_NEAR(var / n, 1.0, 0.03);
  EXPECT_NEAR(corner_var / (3 * fields), 1.0, 0.4);  // 120 samples: sd of the estimate ~0.13
  const int d[3] = {1, 2, 4};
  for (int i = 0; i < 3; ++i) {
    const double model = std::exp(-d[i] * d[i] / (4 * s * s));
    std::cout << "lag " << d[i] << " px: correlation " << lag[i] / var << " (model " << model << ")\n";
    EXPECT_NEAR(lag[i] / var, model, 0.03);
  }
  // s = 0: independent pixels.
  const std::vector<float> white = synth::correlated_normal_field(3, W, H, 0.0);
  double c = 0, w2 = 0;
  for (int i = 0; i + 1 < W * H; ++i) c += white[i] * white[i + 1], w2 += white[i] * white[i];
  EXPECT_NEAR(c / w2, 0.0, 0.02);
}

TEST(SynthRender, DepthLevelsAreSpacedLikeRealFr3Frames) {
  // Measured between consecutive depth levels of the real fr3/structure_texture_near frames
  // of ../shared/data: 2.92e-3 z^2 (z 0.9-2.6 m). Model: z^2 * step / (f_ir * baseline).
  const synth::Scene scene = synth::build_scene(synth::parse_category("structure_notexture_far"), 4);
  synth::RenderSettings s;
  s.depth.noise_coeff = 0;  // quantization only
  const synth::RenderedFrame f = synth::render_frame(scene, scene.nominal_T_wc, s, 0);
  std::vector<int> levels(f.depth.begin(), f.depth.end());
  std::sort(levels.begin(), levels.end());
  levels.erase(std::unique(levels.begin(), levels.end()), levels.end());
  std::vector<double> k;
  for (std::size_t i = 1; i < levels.size(); ++i) {
    if (levels[i - 1] == 0) continue;
    const double z0 = levels[i - 1] / 5000.0, z1 = levels[i] / 5000.0, zm = 0.5 * (z0 + z1);
    k.push_back((z1 - z0) / (zm * zm));
  }
  ASSERT_GT(k.size(), 50u);
  std::nth_element(k.begin(), k.begin() + k.size() / 2, k.end());
  std::cout << "depth level spacing / z^2: " << k[k.size() / 2] << " (real fr3 2.92e-3)\n";
  EXPECT_NEAR(k[k.size() / 2], 2.92e-3, 0.05 * 2.92e-3);
}
