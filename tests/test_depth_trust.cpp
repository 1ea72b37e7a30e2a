// The depth trust test (odometry/depth_trust.h) and method robust: the statistic against its
// closed form, and on a rendered pair with exact depth (the test must not fire) against the
// same pair with the current depth image warped by a known bias (it must fire, and the
// estimate must then be the photometric one).
#include <sys/types.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "odometry/depth_trust.h"
#include "odometry/io/tum_dataset.h"
#include "odometry/synth/sequence.h"
#include "odometry/tracker.h"
#include "solvers/error.h"

namespace fs = std::filesystem;
using namespace bivo::odometry;

namespace {

bivo::solvers::QuadraticModel model(const Eigen::MatrixXd& H, const Eigen::VectorXd& b) {
  bivo::solvers::QuadraticModel m;
  m.a = 1.0;
  m.H = H;
  m.b = b;
  return m;
}

}  // namespace

// T = b^T H^-1 b / sigma^2 and the step -H^-1 b, on a rotated diagonal H.
TEST(DepthTrust, StatisticIsTheNewtonStepLengthInThePhotometricMetric) {
  Eigen::VectorXd h(6), c(6);
  h << 1, 2, 4, 8, 16, 32;
  c << 1, -2, 3, -4, 5, -6;
  const Eigen::MatrixXd Q =
      Eigen::MatrixXd(Eigen::HouseholderQR<Eigen::MatrixXd>(Eigen::MatrixXd::Random(6, 6)).householderQ());
  const Eigen::MatrixXd H = Q * h.asDiagonal() * Q.transpose();
  const Eigen::VectorXd b = Q * c;
  const double sigma = 2.0;
  double expected = 0.0;
  for (int k = 0; k < 6; ++k) expected += c[k] * c[k] / h[k];
  expected /= sigma * sigma;
  const DepthTrust t = photometric_distance(model(H, b), sigma);
  EXPECT_NEAR(t.statistic, expected, 1e-10 * expected);
  EXPECT_EQ(t.rank, 6);
  const Eigen::VectorXd step = -H.ldlt().solve(b);
  EXPECT_LT((t.step - step).norm(), 1e-10 * step.norm());
  // Along the step the model of F_I falls by b^T H^-1 b: the statistic times sigma^2.
  EXPECT_NEAR(model(H, b).value(Eigen::VectorXd::Zero(6)) - model(H, b).value(t.step), expected * sigma * sigma,
              1e-9 * expected * sigma * sigma);
}

// A direction without photometric information (a textureless image) cannot contradict the
// depth objective: the gradient's component along it is ignored.
TEST(DepthTrust, DirectionsWithoutInformationDoNotCount) {
  Eigen::VectorXd h(6), c(6);
  h << 0, 2, 4, 8, 16, 32;
  c << 100, 2, 0, 0, 0, 0;
  const DepthTrust t = photometric_distance(model(h.asDiagonal(), c), 1.0);
  EXPECT_EQ(t.rank, 5);
  EXPECT_NEAR(t.statistic, 2.0, 1e-12);
  EXPECT_EQ(photometric_distance(model(Eigen::MatrixXd::Zero(6, 6), c), 1.0).statistic, 0.0);
  EXPECT_EQ(photometric_distance(model(h.asDiagonal(), c), 0.0).statistic, 0.0);
  EXPECT_THROW(photometric_distance(model(Eigen::MatrixXd::Identity(3, 3), c.head(3)), 1.0), bivo::Error);
  Eigen::VectorXd bad = c;
  bad[0] = std::nan("");
  EXPECT_THROW(photometric_distance(model(h.asDiagonal(), bad), 1.0), bivo::Error);
}

namespace {

struct RenderedPair {
  io::TumSequence sequence;
  io::RgbdImage reference, current;
  Eigen::Isometry3d truth;
};

// Frames 1 and 2 of a textured near rendering (exact, unbiased depth with the sensor's noise).
RenderedPair render_pair(const fs::path& out) {
  fs::remove_all(out);
  synth::SynthOptions o;
  o.category = synth::parse_category("structure_texture_near");
  o.frames = 3;
  o.seed = 11;
  o.threads = 1;
  const std::string dir = synth::render_sequence(o, out.string());
  RenderedPair p;
  p.sequence = io::open_tum_sequence(dir);
  p.reference = io::load_rgbd_image(p.sequence.frames[1]);
  p.current = io::load_rgbd_image(p.sequence.frames[2], p.reference.width, p.reference.height);
  p.truth =
      *io::groundtruth_motion(*p.sequence.groundtruth, p.sequence.frames[1].rgb_time, p.sequence.frames[2].rgb_time);
  return p;
}

PairResult estimate(const RenderedPair& p, const io::RgbdImage& current, const std::string& method,
                    double trust = TrackerOptions{}.policy.trust) {
  TrackerOptions o;
  o.method = method;
  o.policy.trust = trust;
  // The trust test of joint's own estimate (plain r_D, joint's balance): robust's defaults
  // make the depth objective pull less, which is what the test must see through here.
  o.policy.robust_kappa = 1.0;
  o.problem.depth_noise_exponent = 0;
  // T is read at converged estimates: at the default step tolerance a level may end one
  // step early, and that remainder alone can weigh as much as a 3 % bias at full resolution.
  o.step_tolerance = 1e-6;
  const PreparedFrame ref = prepare_frame(p.reference, p.sequence.intrinsics, o.levels);
  const PreparedFrame cur = prepare_frame(current, p.sequence.intrinsics, o.levels);
  return estimate_motion(ref, cur, Eigen::Isometry3d::Identity(), o);
}

// The current depth image with every measurement multiplied by field(u, v).
io::RgbdImage warped(const io::RgbdImage& image, const std::function<double(int, int)>& field) {
  io::RgbdImage out = image;
  for (int v = 0; v < out.height; ++v) {
    for (int u = 0; u < out.width; ++u) out.depth[std::size_t(v) * out.width + u] *= float(field(u, v));
  }
  return out;
}

}  // namespace

TEST(DepthTrust, FiresOnBiasedDepthAndNotOnExactDepth) {
  const fs::path out = fs::temp_directory_path() / ("bivo_test_depth_trust_" + std::to_string(::getpid()));
  const RenderedPair p = render_pair(out);
  // A threshold between the statistics of exact and biased depth measured below (the default,
  // PolicyParameters::trust, leaves the test off).
  const double threshold = 1000.0;
  const PairResult clean = estimate(p, p.current, "robust", threshold);
  // 3 % too far everywhere (the Kinect-class scale error), and a radial field reaching +3 %
  // in the corners (lens-like distortion of the depth): the depth term pulls the translation.
  const io::RgbdImage scaled_image = warped(p.current, [](int, int) { return 1.03; });
  const double w = p.current.width, h = p.current.height;
  const auto radial = [w, h](int u, int v) {
    const double x = (u - 0.5 * w) / (0.5 * w), y = (v - 0.5 * h) / (0.5 * h);
    return 1.0 + 0.015 * (x * x + y * y);
  };
  const io::RgbdImage bent_image = warped(p.current, radial);
  const PairResult scaled = estimate(p, scaled_image, "robust", threshold),
                   bent = estimate(p, bent_image, "robust", threshold);
  const PairResult single_scaled = estimate(p, scaled_image, "single"),
                   joint_scaled = estimate(p, scaled_image, "joint");
  const auto err = [&](const PairResult& r) { return io::pose_error(r.T_21, p.truth); };
  // The statistic at every level, with the fallback never taken (threshold beyond reach).
  std::vector<std::vector<double>> statistics;
  for (const io::RgbdImage* im : {&p.current, &scaled_image, &bent_image}) {
    const PairResult never = estimate(p, *im, "robust", 0.5 * PolicyParameters::kTrustOff);
    EXPECT_EQ(never.relaxed_levels, 0);
    // Off (the default), T is not evaluated, and evaluating it never moves the estimate.
    const PairResult off = estimate(p, *im, "robust");
    EXPECT_TRUE(std::isnan(off.trust));
    EXPECT_TRUE(off.T_21.matrix() == never.T_21.matrix());
    statistics.emplace_back();
    for (const auto& l : never.levels) statistics.back().push_back(l.trust);
  }
  for (std::size_t k = 0; k < 3; ++k) {
    std::printf("[ trust statistic per level, coarse to fine, %s ]", k == 0 ? "exact" : k == 1 ? "x1.03" : "radial");
    for (double t : statistics[k]) std::printf(" %.1f", t);
    std::printf(" (threshold %.1f)\n", threshold);
  }
  std::printf("[ x1.03 depth ] single %.2f mm, joint %.2f mm, robust %.2f mm (%d levels photometric)\n",
              1e3 * err(single_scaled).translation_m, 1e3 * err(joint_scaled).translation_m,
              1e3 * err(scaled).translation_m, scaled.relaxed_levels);
  ASSERT_EQ(clean.levels.size(), 4u);
  for (double t : statistics[0]) EXPECT_LT(t, threshold) << "exact depth must be trusted at every level";
  EXPECT_EQ(clean.relaxed_levels, 0);
  // The biased statistics exceed the threshold at some level (then the test fires and
  // latches), and at full resolution the biased depth lies several times further from the
  // photometric estimate than the exact one (measured: 19 exact, 629 x1.03, 1887 radial).
  const auto largest = [](const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()); };
  EXPECT_GT(largest(statistics[1]), threshold);
  EXPECT_GT(largest(statistics[2]), threshold);
  EXPECT_GT(statistics[1].back(), 3.0 * statistics[0].back());
  EXPECT_GT(statistics[2].back(), 3.0 * statistics[0].back());
  // Fired (at some level, then latched): the finest level is photometric.
  EXPECT_TRUE(scaled.levels.back().relaxed);
  EXPECT_TRUE(bent.levels.back().relaxed);
  // The fallback keeps the photometric accuracy on the biased pair.
  EXPECT_LE(err(scaled).translation_m, 1.2 * err(single_scaled).translation_m + 2e-4);
  fs::remove_all(out);
}
