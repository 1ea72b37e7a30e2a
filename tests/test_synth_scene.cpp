// The scenes' geometry against independent oracles: in the nominal view of every structure
// category both the floor and the zig-zag panels are in view (pixels classified by their
// back-projected world points); depth alone constrains all six degrees of freedom on the
// structure scenes and leaves three unconstrained on the plane (eigenvalues of the
// point-to-plane information matrix); texture twins have identical geometry and depth.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>

#include "odometry/synth/render.h"
#include "odometry/synth/scene.h"

namespace synth = bivo::odometry::synth;

namespace {

synth::RenderSettings noiseless() {
  synth::RenderSettings s;
  s.sensor_noise = false;
  return s;
}

Eigen::Vector3d back_project(const synth::PinholeCamera& K, int u, int v, double z) {
  return {(u - K.cx) / K.fx * z, (v - K.cy) / K.fy * z, z};
}

// Eigenvalues (ascending) of sum_i J_i^T J_i with J_i = [n_i^T, (p_i x n_i)^T]: the
// change of pixel i's distance to its surface plane for a motion [v; w] of the camera's
// points, n from the cross product of the neighbours' back-projections (true depth).
Eigen::VectorXd depth_information_eigenvalues(const synth::RenderedFrame& f, const synth::PinholeCamera& K) {
  Eigen::Matrix<double, 6, 6> info = Eigen::Matrix<double, 6, 6>::Zero();
  const int W = f.width, H = f.height;
  for (int v = 0; v + 1 < H; v += 2) {
    for (int u = 0; u + 1 < W; u += 2) {
      const std::size_t i = static_cast<std::size_t>(v) * W + u;
      if (f.depth[i] == 0 || f.depth[i + 1] == 0 || f.depth[i + W] == 0) continue;  // measured pixels only
      const Eigen::Vector3d p = back_project(K, u, v, f.true_depth[i]);
      const Eigen::Vector3d n = (back_project(K, u + 1, v, f.true_depth[i + 1]) - p)
                                    .cross(back_project(K, u, v + 1, f.true_depth[i + W]) - p)
                                    .normalized();
      Eigen::Matrix<double, 6, 1> J;
      J << n, p.cross(n);
      info += J * J.transpose();
    }
  }
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>>(info).eigenvalues();
}

}  // namespace

TEST(SynthScene, FloorAndPanelsAreBothInTheNominalViewOfEveryStructureCategory) {
  // Oracle: a pixel's world point (T_wc * back-projected true depth) on z = 0 is floor; one
  // above the floor and within the zig-zag's band 0 <= y <= 0.4 m is a panel.
  for (const auto& c : synth::all_categories()) {
    if (!c.structure) continue;
    const synth::Scene scene = synth::build_scene(c, 1);
    const synth::RenderSettings s = noiseless();
    const synth::RenderedFrame f = synth::render_frame(scene, scene.nominal_T_wc, s, 0);
    int floor = 0, panels = 0, floor_with_depth = 0, panels_with_depth = 0;
    for (int v = 0; v < f.height; ++v) {
      for (int u = 0; u < f.width; ++u) {
        const std::size_t i = static_cast<std::size_t>(v) * f.width + u;
        if (f.true_depth[i] <= 0) continue;
        const Eigen::Vector3d P = scene.nominal_T_wc * back_project(s.camera, u, v, f.true_depth[i]);
        const bool measured = f.depth[i] > 0;
        if (std::fabs(P.z()) < 1e-4) {
          ++floor;
          floor_with_depth += measured;
        } else if (P.y() > -1e-4 && P.y() < 0.4 + 1e-4 && P.z() <= 1.0 + 1e-4) {
          ++panels;
          panels_with_depth += measured;
        }
      }
    }
    const double n = f.width * f.height;
    std::cout << c.name() << ": floor " << floor / n << " (with depth " << floor_with_depth / n << "), panels "
              << panels / n << " (with depth " << panels_with_depth / n << ") of the image\n";
    EXPECT_GT(floor_with_depth, 0.2 * n) << c.name();
    EXPECT_GT(panels_with_depth, 0.4 * n) << c.name();
  }
}

TEST(SynthScene, DepthAloneConstrainsAllSixDegreesOfFreedomOnStructureNotOnThePlane) {
  for (const auto& c : synth::all_categories()) {
    if (!c.texture) continue;  // geometry is the texture twin's (next test)
    const synth::Scene scene = synth::build_scene(c, 2);
    const synth::RenderSettings s = noiseless();
    const synth::RenderedFrame f = synth::render_frame(scene, scene.nominal_T_wc, s, 0);
    const Eigen::VectorXd ev = depth_information_eigenvalues(f, s.camera);
    const double ratio = ev(0) / ev(5);
    std::cout << c.name() << ": eigenvalues of the depth information " << ev.transpose() << ", smallest/largest "
              << ratio << "\n";
    if (c.structure) {
      EXPECT_GT(ratio, 1e-3) << c.name();  // the zig-zag's two normals and the floor's span R^3
    } else {
      // One plane: sliding along it (2) and turning about its normal (1) change no depth.
      EXPECT_LT(ev(2) / ev(5), 1e-7) << c.name();
      EXPECT_GT(ev(3) / ev(5), 1e-3) << c.name();
    }
  }
}

TEST(SynthScene, TextureTwinsHaveTheSameGeometryAndDepthOnlyTheColourDiffers) {
  for (bool structure : {true, false}) {
    synth::SynthCategory textured, plain;
    textured.structure = plain.structure = structure;
    plain.texture = false;
    const synth::Scene a = synth::build_scene(textured, 5), b = synth::build_scene(plain, 5);
    ASSERT_EQ(a.panels.size(), b.panels.size());
    EXPECT_TRUE(a.nominal_T_wc.isApprox(b.nominal_T_wc, 0.0));
    const Eigen::Isometry3d pose = a.nominal_T_wc * Eigen::Translation3d(0.05, -0.02, 0.1);
    const synth::RenderSettings s;  // with sensor noise: the same seed gives the same depth noise
    const synth::RenderedFrame fa = synth::render_frame(a, pose, s, 3), fb = synth::render_frame(b, pose, s, 3);
    EXPECT_EQ(fa.true_depth, fb.true_depth);
    EXPECT_EQ(fa.depth, fb.depth);
    EXPECT_NE(fa.rgb, fb.rgb);
  }
}
