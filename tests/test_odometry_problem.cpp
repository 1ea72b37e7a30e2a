// The RGB-D odometry problem on real TUM frames (and the plane scene): analytic Jacobians against central finite
// differences, the accumulated quadratic models against the full J / r / w, and evaluate()
// against the weighted sums of residuals().
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>

#include "odometry/io/pose_error.h"
#include "odometry/io/tum_dataset.h"
#include "odometry/rgbd_problem.h"
#include "odometry/rgbd_pyramid.h"
#include "solvers/error.h"
#include "solvers/geometry/se3.h"
#include "tests/support/plane_scene.h"

using namespace bivo;
using namespace bivo::odometry;
using namespace bivo::odometry::io;
namespace se3 = bivo::solvers::se3;

namespace {

const std::string kData = std::string(BIVO_SHARED_DIR) + "/data/tum/";

struct Pair {
  RgbdPyramid reference, current;
  Eigen::Isometry3d truth;  // ground-truth T_21
};

Pair load_pair(const std::string& sequence, int i, int j, int levels) {
  const TumSequence seq = open_tum_sequence(kData + sequence);
  Pair p;
  p.reference = build_pyramid(load_rgbd_image(seq.frames.at(i)), seq.intrinsics, levels);
  p.current = build_pyramid(load_rgbd_image(seq.frames.at(j)), seq.intrinsics, levels);
  const auto gt = groundtruth_motion(*seq.groundtruth, seq.frames[i].rgb_time, seq.frames[j].rgb_time);
  if (!gt) throw Error("no ground truth for the test pair");
  p.truth = *gt;
  return p;
}

bool have_data() { return std::filesystem::exists(kData + "rgbd_dataset_freiburg1_desk"); }

struct FdReport {
  int compared = 0, kinks = 0, failures = 0;
  double max_rel = 0.0;
};

// Central differences along each tangent direction, with steps h and h/2. Both agree to
// O(h^2) where the residual is smooth; a row whose two estimates disagree (> 1e-5 relative)
// has a pixel-cell border of the bilinear interpolant (derivative jump) or a validity change
// within +-h: it is counted as a kink, not compared. On every other row a wrong Jacobian
// shows up in both estimates alike, so it cannot hide.
FdReport check_jacobian(RgbdOdometryProblem& problem, int j, const Eigen::VectorXd& x, double h) {
  const solvers::ResidualData at = problem.residuals(j, x, true);
  const Eigen::Index n = at.r.size();
  Eigen::MatrixXd central(n, 6), central_half(n, 6);
  std::vector<char> smooth(static_cast<std::size_t>(n), 1);
  for (int k = 0; k < 6; ++k) {
    for (const double step : {h, 0.5 * h}) {
      Eigen::VectorXd d = Eigen::VectorXd::Zero(6);
      d(k) = step;
      const auto plus = problem.residuals(j, problem.manifold().retract(x, d), false);
      const auto minus = problem.residuals(j, problem.manifold().retract(x, -d), false);
      (step == h ? central : central_half).col(k) = (plus.r - minus.r) / (2.0 * step);
      for (Eigen::Index i = 0; i < n; ++i) {
        if ((plus.r(i) == 0.0) != (at.r(i) == 0.0) || (minus.r(i) == 0.0) != (at.r(i) == 0.0)) {
          smooth[static_cast<std::size_t>(i)] = 0;
        }
      }
    }
  }
  std::vector<double> norms;
  for (Eigen::Index i = 0; i < n; ++i) norms.push_back(at.J.row(i).norm());
  std::nth_element(norms.begin(), norms.begin() + n / 2, norms.end());
  const double floor = 1e-6 * std::max(norms[static_cast<std::size_t>(n / 2)], 1e-12);
  FdReport rep;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (at.r(i) == 0.0) continue;
    const double scale = std::max(at.J.row(i).norm(), floor);
    if (!smooth[static_cast<std::size_t>(i)] || (central.row(i) - central_half.row(i)).norm() > 1e-5 * scale) {
      ++rep.kinks;
      continue;
    }
    ++rep.compared;
    const double rel = (central.row(i) - at.J.row(i)).norm() / scale;
    rep.max_rel = std::max(rep.max_rel, rel);
    if (rel > 1e-4) ++rep.failures;
  }
  return rep;
}

}  // namespace

TEST(RgbdProblem, JacobiansMatchCentralDifferencesOnRealFrames) {
  if (!have_data()) GTEST_SKIP() << "shared data absent: " << kData;
  for (const auto& [sequence, level] : {std::pair<std::string, int>{"rgbd_dataset_freiburg1_desk", 0},
                                        {"rgbd_dataset_freiburg3_long_office_household", 1}}) {
    const Pair p = load_pair(sequence, 3, 5, 2);  // fr3's ground truth starts at frame 3
    RgbdOdometryProblem problem(p.reference.levels[level], p.current.levels[level]);
    // Near (not at) the true motion so residuals are those a solver meets.
    se3::Vector6d wiggle;
    wiggle << 0.004, -0.003, 0.002, 0.002, -0.003, 0.001;
    const Eigen::VectorXd x = se3::to_ambient(se3::exp(wiggle) * p.truth);
    for (int j : {1, 2}) {
      const FdReport rep = check_jacobian(problem, j, x, 1e-6);
      SCOPED_TRACE(sequence + " level " + std::to_string(level) + " objective " + std::to_string(j));
      std::printf("[ fd ] %s level %d F_%d: %d rows compared, %d at cell borders, max rel err %.3g\n", sequence.c_str(),
                  level, j, rep.compared, rep.kinks, rep.max_rel);
      EXPECT_GT(rep.compared, 10000);
      EXPECT_LT(rep.kinks, rep.compared / 50);  // cell-border rows are rare at h = 1e-6
      EXPECT_EQ(rep.failures, 0) << "max relative error " << rep.max_rel;
      EXPECT_LT(rep.max_rel, 1e-4);
    }
  }
}

// F_D whitened for depth noise growing with z^2: r_D / z^2 and its Jacobian.
TEST(RgbdProblem, WhitenedDepthJacobiansMatchCentralDifferences) {
  if (!have_data()) GTEST_SKIP() << "shared data absent: " << kData;
  const Pair p = load_pair("rgbd_dataset_freiburg1_desk", 3, 5, 2);
  RgbdProblemOptions o;
  o.depth_noise_exponent = 2;
  RgbdOdometryProblem problem(p.reference.levels[1], p.current.levels[1], o);
  se3::Vector6d wiggle;
  wiggle << 0.004, -0.003, 0.002, 0.002, -0.003, 0.001;
  const FdReport rep = check_jacobian(problem, 2, se3::to_ambient(se3::exp(wiggle) * p.truth), 1e-6);
  EXPECT_GT(rep.compared, 10000);
  EXPECT_EQ(rep.failures, 0) << "max relative error " << rep.max_rel;
}

// r_I with the radial brightness term (affine_brightness 2), its c fitted on a pair whose
// images share a fall-off: the term's derivative is in the Jacobian (needs no data files).
TEST(RgbdProblem, RadialBrightnessJacobiansMatchCentralDifferences) {
  io::RgbdImage first = bivo::testing::render_plane(Eigen::Isometry3d::Identity());
  io::RgbdImage second = bivo::testing::render_plane(bivo::testing::camera2());
  bivo::testing::vignette(first, 0.3);
  bivo::testing::vignette(second, 0.3);
  const RgbdPyramid a = build_pyramid(first, bivo::testing::kK, 1), b = build_pyramid(second, bivo::testing::kK, 1);
  RgbdProblemOptions o;
  o.affine_brightness = 2;
  o.radial_prior = 0.0;
  RgbdOdometryProblem problem(a.levels[0], b.levels[0], o);
  const Eigen::VectorXd x = bivo::testing::near_truth();
  problem.linearize(x, {});
  ASSERT_LT(problem.last_stats().brightness_radial, -0.1);
  const FdReport rep = check_jacobian(problem, 1, x, 1e-6);
  EXPECT_GT(rep.compared, 50000);
  // Without the term's derivative ~70,000 rows fail; with it at most a row whose image and
  // fall-off gradients nearly cancel (J near the differences' round-off) misses 1e-4.
  EXPECT_LE(rep.failures, rep.compared / 10000) << "max relative error " << rep.max_rel;
  EXPECT_LT(rep.max_rel, 1e-3);
}

TEST(RgbdProblem, AccumulatedModelsEqualFullResidualData) {
  if (!have_data()) GTEST_SKIP() << "shared data absent: " << kData;
  const Pair p = load_pair("rgbd_dataset_freiburg1_desk", 0, 1, 3);
  RgbdOdometryProblem problem(p.reference.levels[1], p.current.levels[1]);
  // Off the identity: there every reference pixel lands exactly on a cell border of frame 2,
  // where the float and double paths may pick different cells (the interpolant's derivative
  // jumps there), so H would differ by whole rows, not by rounding.
  se3::Vector6d wiggle;
  wiggle << 0.0031, -0.0023, 0.0017, 0.0021, -0.0027, 0.0013;
  const Eigen::VectorXd x = se3::to_ambient(se3::exp(wiggle));
  solvers::LinearizeOptions opt;
  opt.want_full = true;
  solvers::PhaseProfile profile;
  opt.profile = &profile;
  const solvers::Linearization lin = problem.linearize(x, opt);
  ASSERT_TRUE(lin.full1 && lin.full2);
  for (const auto& [model, full] : {std::pair{&lin.f1, &*lin.full1}, std::pair{&lin.f2, &*lin.full2}}) {
    const Eigen::VectorXd wr = full->w.cwiseProduct(full->r);
    const Eigen::MatrixXd H = full->J.transpose() * full->w.asDiagonal() * full->J;
    EXPECT_NEAR(model->a, full->r.dot(wr), 1e-5 * std::abs(model->a));
    // Float per-term products, double totals: agreement to float precision relative to the sum
    // of the terms' magnitudes (b sums terms of both signs that cancel near the optimum).
    const Eigen::VectorXd b_magnitude = full->J.cwiseAbs().transpose() * wr.cwiseAbs();
    EXPECT_LT((model->b - full->J.transpose() * wr).norm(), 1e-5 * b_magnitude.norm());
    const Eigen::MatrixXd H_magnitude = full->J.cwiseAbs().transpose() * full->w.asDiagonal() * full->J.cwiseAbs();
    EXPECT_LT((model->H - H).norm(), 1e-5 * H_magnitude.norm());
    // The model is of full rank on a textured desk.
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(model->H).eigenvalues().minCoeff(), 0.0);
  }
  // residuals() at the linearization point returns the same data (computed in double,
  // the models from float caches: agreement to float precision).
  const auto r1 = problem.residuals(1, x, true);
  EXPECT_LT((r1.r - lin.full1->r).norm(), 1e-5 * r1.r.norm());
  EXPECT_LT((r1.J - lin.full1->J).norm(), 1e-5 * r1.J.norm());
  EXPECT_EQ(r1.w, lin.full1->w);
  // evaluate() at x is a_1, a_2.
  const auto f = problem.evaluate(x);
  EXPECT_NEAR(f[0], lin.f1.a, 1e-9 * lin.f1.a);
  EXPECT_NEAR(f[1], lin.f2.a, 1e-9 * lin.f2.a);
  for (const char* phase : {"residuals", "weights", "normal_equations"}) {
    EXPECT_GT(profile.seconds(phase), 0.0) << phase;
  }
  // Stats agree with the data.
  const auto& s = problem.last_stats();
  EXPECT_GE(s.valid_intensity, (lin.full1->r.array() != 0.0).count());
  EXPECT_LE(s.valid_intensity, (lin.full1->w.array() != 0.0).count());
  EXPECT_NEAR(s.weight_sum_depth, lin.full2->w.sum(), 1e-6 * s.weight_sum_depth);
}

TEST(RgbdProblem, DepthFirstSwapsTheObjectives) {
  if (!have_data()) GTEST_SKIP() << "shared data absent: " << kData;
  const Pair p = load_pair("rgbd_dataset_freiburg1_desk", 0, 1, 3);
  RgbdProblemOptions o;
  RgbdOdometryProblem a(p.reference.levels[2], p.current.levels[2], o);
  o.depth_first = true;
  RgbdOdometryProblem b(p.reference.levels[2], p.current.levels[2], o);
  const Eigen::VectorXd x = se3::to_ambient(p.truth);
  const auto la = a.linearize(x, {});
  const auto lb = b.linearize(x, {});
  EXPECT_EQ(la.f1.a, lb.f2.a);
  EXPECT_EQ(la.f2.a, lb.f1.a);
  EXPECT_EQ((la.f2.H - lb.f1.H).norm(), 0.0);
  const auto ea = a.evaluate(x), eb = b.evaluate(x);
  EXPECT_EQ(ea[0], eb[1]);
  EXPECT_EQ(b.residuals(1, x, false).r, a.residuals(2, x, false).r);
}

TEST(RgbdProblem, TrueMotionLowersBothObjectives) {
  if (!have_data()) GTEST_SKIP() << "shared data absent: " << kData;
  const Pair p = load_pair("rgbd_dataset_freiburg1_desk", 0, 2, 2);
  RgbdOdometryProblem problem(p.reference.levels[1], p.current.levels[1]);
  const Eigen::VectorXd truth = se3::to_ambient(p.truth);
  problem.linearize(truth, {});  // fix the weights at the truth
  const auto f_truth = problem.evaluate(truth);
  se3::Vector6d off;
  off << 0.02, 0, 0, 0, 0.01, 0;
  const auto f_off = problem.evaluate(se3::to_ambient(se3::exp(off) * p.truth));
  EXPECT_LT(f_truth[0], 0.8 * f_off[0]);
  EXPECT_LT(f_truth[1], 0.8 * f_off[1]);
}

TEST(RgbdProblem, BadInputIsRejected) {
  RgbdLevel a, b;
  a.intensity = {4, 4, std::vector<float>(16, 1.0f)};
  a.depth = {4, 4, std::vector<float>(16, 1.0f)};
  b.intensity = {4, 3, std::vector<float>(12, 1.0f)};
  b.depth = {4, 3, std::vector<float>(12, 1.0f)};
  EXPECT_THROW(RgbdOdometryProblem(a, b), Error);
  RgbdOdometryProblem ok(a, a);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(7);
  EXPECT_THROW(ok.evaluate(x), Error);  // zero quaternion
  x(6) = 1.0;
  x(0) = std::nan("");
  EXPECT_THROW(ok.linearize(x, {}), Error);
  EXPECT_THROW(ok.residuals(3, Eigen::VectorXd::Unit(7, 6), false), Error);
}

// The tracker's exact finish switches a problem built with reference-side gradients to the
// current-side ones: its linearization must then be that of a problem built forward (a second
// construction as the oracle), and a forward-built problem has no reference gradients to
// switch to.
TEST(RgbdProblem, SwitchingToForwardGradientsEqualsAForwardProblem) {
  if (!have_data()) GTEST_SKIP() << "shared data absent: " << kData;
  const Pair p = load_pair("rgbd_dataset_freiburg1_desk", 0, 2, 2);
  RgbdProblemOptions inverse_options;
  inverse_options.jacobian = JacobianKind::kInverse;
  RgbdOdometryProblem switched(p.reference.levels[1], p.current.levels[1], inverse_options);
  RgbdOdometryProblem forward(p.reference.levels[1], p.current.levels[1]);
  se3::Vector6d off;
  off << 0.01, -0.005, 0.0, 0.002, 0.004, 0.0;
  const Eigen::VectorXd x = se3::to_ambient(se3::exp(off) * p.truth);
  const auto before = switched.linearize(x, {});
  switched.set_jacobian(JacobianKind::kForward);
  const auto after = switched.linearize(x, {});
  const auto oracle = forward.linearize(x, {});
  // Reference-side gradients give a different model at a pose off the optimum ...
  EXPECT_GT((before.f1.H - oracle.f1.H).norm(), 1e-3 * oracle.f1.H.norm());
  // ... the switched problem gives the forward one (same weights: both estimated at x).
  EXPECT_LT((after.f1.H - oracle.f1.H).norm(), 1e-9 * oracle.f1.H.norm());
  EXPECT_LT((after.f1.b - oracle.f1.b).norm(), 1e-9 * oracle.f1.b.norm());
  EXPECT_LT((after.f2.H - oracle.f2.H).norm(), 1e-9 * oracle.f2.H.norm());
  EXPECT_NEAR(after.f1.a, oracle.f1.a, 1e-9 * oracle.f1.a);
  EXPECT_THROW(forward.set_jacobian(JacobianKind::kInverse), Error);
  EXPECT_THROW(forward.set_jacobian(JacobianKind::kMethodDefault), Error);
}

// evaluate_only() (a solve's last step) sums F in a warp that writes nothing. Oracles: the
// same problem's evaluate() afterwards and a second problem's evaluate(), bit for bit, for
// every kernel width and weight model; and the linearization it must leave in place.
TEST(RgbdProblem, EvaluateOnlyGivesEvaluatesValuesAndKeepsTheLinearization) {
  if (!have_data()) GTEST_SKIP() << "shared data absent: " << kData;
  const Pair p = load_pair("rgbd_dataset_freiburg1_desk", 0, 1, 2);
  se3::Vector6d off;
  off << 0.004, -0.003, 0.002, 0.003, -0.002, 0.001;
  const Eigen::VectorXd x0 = se3::to_ambient(p.truth);
  const Eigen::VectorXd x1 = se3::to_ambient(se3::exp(off) * p.truth);
  for (const KernelIsa isa : {KernelIsa::kScalar, KernelIsa::kAvx2, KernelIsa::kAvx512Vl, KernelIsa::kAvx512}) {
    if (!kernels_available(isa)) continue;
    for (const bool joint : {false, true}) {
      SCOPED_TRACE(std::string(to_string(isa)) + (joint ? " joint" : " t-distribution"));
      RgbdProblemOptions o;
      o.joint_weights = joint;
      RgbdOdometryProblem problem(p.reference.levels[1], p.current.levels[1], o);
      RgbdOdometryProblem oracle(p.reference.levels[1], p.current.levels[1], o);
      problem.set_kernel_isa(isa);
      oracle.set_kernel_isa(isa);
      const auto lin = problem.linearize(x0, {});
      oracle.linearize(x0, {});
      const auto f_only = problem.evaluate_only(x1);
      const auto f_oracle = oracle.evaluate(x1);
      EXPECT_EQ(f_only[0], f_oracle[0]);
      EXPECT_EQ(f_only[1], f_oracle[1]);
      EXPECT_GT(f_only[0], 0.0);
      EXPECT_NE(f_only[0], lin.f1.a) << "x1 must be a point of its own";
      // The buffers still hold x0: the models rebuilt from them (want_full bypasses the
      // cached linearization, the stored weights are kept) are those of x0.
      solvers::LinearizeOptions rebuild;
      rebuild.want_full = true;
      rebuild.update_weights = false;
      const auto again = problem.linearize(x0, rebuild);
      EXPECT_NEAR(again.f1.a, lin.f1.a, 1e-12 * lin.f1.a);
      EXPECT_NEAR(again.f2.a, lin.f2.a, 1e-12 * lin.f2.a);
      EXPECT_LT((again.f1.H - lin.f1.H).norm(), 1e-12 * lin.f1.H.norm());
      EXPECT_LT((again.f2.b - lin.f2.b).norm(), 1e-12 * lin.f2.b.norm());
      const auto f_after = problem.evaluate(x1);
      EXPECT_EQ(f_after[0], f_only[0]);
      EXPECT_EQ(f_after[1], f_only[1]);
    }
  }
}
