// The float per-pixel kernels of RgbdOdometryProblem (odometry/kernels/rgbd_kernels.h) against
// independent references: the double path (full residual data, what the finite-difference
// tests check), the other instruction set, other thread counts (bit-identical results), and
// first-order image motion computed point by point. A procedural scene (a slanted textured
// plane seen from two poses, with holes in the depth) needs no data files.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "odometry/image_statistics.h"
#include "odometry/rgbd_problem.h"
#include "odometry/robust_weights.h"
#include "odometry/tracker.h"
#include "solvers/geometry/se3.h"
#include "solvers/outer_loop.h"
#include "solvers/scalarization.h"
#include "tests/support/plane_scene.h"

using namespace bivo;
using namespace bivo::odometry;
namespace se3 = bivo::solvers::se3;

using bivo::testing::kK;
using bivo::testing::near_truth;
using bivo::testing::rel;
using bivo::testing::render_plane;
using bivo::testing::scene;

TEST(RgbdKernels, FloatModelsMatchTheDoublePathsFullData) {
  for (const KernelIsa isa : {KernelIsa::kScalar, KernelIsa::kAvx2, KernelIsa::kAvx512Vl, KernelIsa::kAvx512}) {
    for (const int exponent : {0, 1, 2, 3}) {
      if (!kernels_available(isa)) continue;
      SCOPED_TRACE(std::string(to_string(isa)) + ", depth noise exponent " + std::to_string(exponent));
      RgbdProblemOptions options;
      options.depth_noise_exponent = exponent;
      RgbdOdometryProblem p(scene().reference.pyramid.levels[0], scene().current.pyramid.levels[0], options);
      p.set_kernel_isa(isa);
      solvers::LinearizeOptions o;
      o.want_full = true;
      const solvers::Linearization lin = p.linearize(near_truth(), o);
      for (const auto& [model, full] : {std::pair{&lin.f1, &*lin.full1}, std::pair{&lin.f2, &*lin.full2}}) {
        const solvers::QuadraticModel want = solvers::quadratic_model_of(*full);
        EXPECT_LT(std::abs(model->a - want.a), 2e-4 * want.a);  // float warp vs double warp
        EXPECT_LT(rel(model->b, want.b), 2e-4);
        EXPECT_LT(rel(model->H, want.H), 2e-4);
      }
      EXPECT_GT(p.last_stats().valid_intensity, 0.8 * p.num_terms());
    }
  }
}

// The eight- and sixteen-lane kernels against the one-lane kernels (the scene's term count is
// not a multiple of 16, so the last lane group of each is partly padding).
TEST(RgbdKernels, ScalarAndVectorKernelsAgree) {
  const RgbdLevel& a = scene().reference.pyramid.levels[0];
  const RgbdLevel& b = scene().current.pyramid.levels[0];
  for (const auto& [isa, joint] : {std::pair{KernelIsa::kAvx2, false}, std::pair{KernelIsa::kAvx512, false},
                                   std::pair{KernelIsa::kAvx2, true}, std::pair{KernelIsa::kAvx512, true}}) {
    if (!kernels_available(isa)) continue;
    SCOPED_TRACE(std::string(to_string(isa)) + (joint ? ", joint weights" : ""));
    RgbdProblemOptions options;
    options.joint_weights = joint;  // the 2x2 scale's passes and the joint weight model
    RgbdOdometryProblem scalar(a, b, options), avx2(a, b, options);
    EXPECT_NE(scalar.num_terms() % 16, 0);
    scalar.set_kernel_isa(KernelIsa::kScalar);
    avx2.set_kernel_isa(isa);
    const Eigen::VectorXd x = near_truth();
    const auto ls = scalar.linearize(x, {}), lv = avx2.linearize(x, {});
    EXPECT_LT(std::abs(ls.f1.a - lv.f1.a), 1e-5 * ls.f1.a);
    EXPECT_LT(rel(lv.f1.H, ls.f1.H), 1e-5);
    EXPECT_LT(rel(lv.f2.H, ls.f2.H), 1e-5);
    EXPECT_LT(rel(lv.f1.b, ls.f1.b), 1e-4);
    EXPECT_NEAR(scalar.last_stats().valid_intensity, avx2.last_stats().valid_intensity, 5);
    EXPECT_NEAR(scalar.last_stats().sigma_depth, avx2.last_stats().sigma_depth, 1e-5 * scalar.last_stats().sigma_depth);
    EXPECT_NEAR(scalar.last_stats().joint_scale.correlation(), avx2.last_stats().joint_scale.correlation(), 1e-5);
    const Eigen::VectorXd x2 = se3::to_ambient(scene().T_21);
    const auto fs = scalar.evaluate(x2), fv = avx2.evaluate(x2);
    EXPECT_LT(std::abs(fs[0] - fv[0]), 1e-5 * fs[0]);
    // At the truth F_D is ~1e-14 (an exact plane): below that, float rounding (FMA or not) rules.
    EXPECT_LT(std::abs(fs[1] - fv[1]), std::max(1e-5 * fs[1], 1e-8));
  }
}

// Each kernel's t-scale pass against its closed form, one residual value at a time (sixteen
// equal terms, so no lane sum can average a per-term error away): sum (nu + 1) r^2 / (nu +
// r^2 / s^2) and its slope. The sixteen-lane kernel's approximate reciprocal must stay
// within float rounding here.
TEST(RgbdKernels, ScaleSumsMatchTheClosedFormTermByTerm) {
  const float nu = 5.0f, inv_scale2 = 1.0f / 36.0f;
  for (const KernelIsa isa : {KernelIsa::kScalar, KernelIsa::kAvx2, KernelIsa::kAvx512Vl, KernelIsa::kAvx512}) {
    if (!kernels_available(isa)) continue;
    SCOPED_TRACE(to_string(isa));
    for (double r = 0.01; r < 1e3; r *= 1.0173) {
      const std::vector<float> terms(16, static_cast<float>(r));
      const ScaleSums s = kernels(isa).t_scale_sums(terms.data(), 0, terms.size(), nu, inv_scale2);
      const double r2 = double(terms[0]) * terms[0], a = r2 * inv_scale2, t = 1.0 / (a + nu);
      const double sum = 16.0 * (nu + 1.0) * r2 * t, slope = sum * a * t;
      EXPECT_NEAR(s.sum, sum, 3e-6 * sum) << "r = " << r;
      EXPECT_NEAR(s.slope, slope, 3e-6 * slope) << "r = " << r;
    }
  }
}

TEST(RgbdKernels, Avx512VlKernelsAreBitIdenticalToAvx2) {
  if (!kernels_available(KernelIsa::kAvx2) || !kernels_available(KernelIsa::kAvx512Vl)) {
    GTEST_SKIP() << "no AVX2 or AVX-512VL kernels on this build / CPU";
  }
  const RgbdLevel& a = scene().reference.pyramid.levels[0];
  const RgbdLevel& b = scene().current.pyramid.levels[0];
  struct Case {
    const char* name;
    RgbdProblemOptions options;
  };
  std::vector<Case> cases(4);
  cases[0].name = "both objectives, forward";
  cases[1].name = "joint weights, inverse";
  cases[1].options.joint_weights = true;
  cases[1].options.jacobian = JacobianKind::kInverse;
  cases[2].name = "intensity only, esm";
  cases[2].options.model_f2 = false;
  cases[2].options.jacobian = JacobianKind::kEsm;
  cases[3].name = "huber, two threads";
  cases[3].options.weights.kind = WeightKind::kHuber;
  cases[3].options.threads = 2;
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    RgbdOdometryProblem avx2(a, b, c.options), vl(a, b, c.options);
    avx2.set_kernel_isa(KernelIsa::kAvx2);
    vl.set_kernel_isa(KernelIsa::kAvx512Vl);
    const Eigen::VectorXd x = near_truth();
    const auto l2 = avx2.linearize(x, {}), lv = vl.linearize(x, {});
    EXPECT_EQ(lv.f1.a, l2.f1.a);
    EXPECT_EQ(lv.f2.a, l2.f2.a);
    EXPECT_TRUE(lv.f1.H == l2.f1.H && lv.f2.H == l2.f2.H);
    EXPECT_TRUE(lv.f1.b == l2.f1.b && lv.f2.b == l2.f2.b);
    EXPECT_EQ(vl.last_stats().sigma_intensity, avx2.last_stats().sigma_intensity);
    EXPECT_EQ(vl.last_stats().sigma_depth, avx2.last_stats().sigma_depth);
    EXPECT_EQ(vl.last_stats().valid_depth, avx2.last_stats().valid_depth);
    const Eigen::VectorXd x2 = se3::to_ambient(scene().T_21);
    EXPECT_EQ(vl.evaluate(x2), avx2.evaluate(x2));
  }
}

// estimate_scales runs both objectives' t fixed points in shared passes: each scale must be
// bit for bit what estimate_scale finds alone (the oracle), also when one iteration stops
// before the other (different warm starts), when one objective has no valid residual, with
// Huber weights, and on two threads; and each must satisfy its fixed-point equation.
TEST(RobustWeights, SharedScalePassesGiveEachObjectivesOwnScale) {
  const std::size_t n = 3 * kChunkTerms + 77;
  std::vector<float> ri(padded_terms(n), 0.0f), rd(padded_terms(n), 0.0f);
  std::vector<std::uint8_t> flags(padded_terms(n), 0);
  ResidualSet si{ri.data(), flags.data(), 1, 0, 0.0}, sd{rd.data(), flags.data(), 2, 0, 0.0};
  for (std::size_t k = 0; k < n; ++k) {
    const double t = 0.37 * double(k);
    ri[k] = static_cast<float>(0.05 * std::sin(t) + (k % 17 == 0 ? 0.6 : 0.0));  // outliers
    rd[k] = static_cast<float>(0.004 * std::cos(1.3 * t));
    flags[k] = k % 5 == 0 ? 1 : 3;  // every fifth term has no depth residual
    if (flags[k] & 2) {
      sd.valid += 1;
      sd.sum_squares += double(rd[k]) * rd[k];
    } else {
      rd[k] = 0.0f;
    }
    si.valid += 1;
    si.sum_squares += double(ri[k]) * ri[k];
  }
  const KernelTable& kernels = default_kernels();
  WeightOptions o;
  for (int threads : {1, 2}) {
    for (const std::array<double, 2> start : {std::array<double, 2>{0.0, 0.0}, {0.04, 0.1}, {0.5, 0.003}}) {
      const auto both = estimate_scales(si, sd, n, o, start, kernels, threads);
      EXPECT_EQ(both[0], estimate_scale(si, n, o, start[0], kernels, threads));
      EXPECT_EQ(both[1], estimate_scale(sd, n, o, start[1], kernels, threads));
      for (int j = 0; j < 2; ++j) {  // sigma^2 = mean over valid terms of r^2 (nu + 1) / (nu + r^2 / sigma^2)
        const std::vector<float>& r = j == 0 ? ri : rd;
        const double s2 = both[j] * both[j];
        double g = 0.0;
        for (std::size_t k = 0; k < n; ++k) g += double(r[k]) * r[k] * (o.nu + 1.0) / (o.nu + double(r[k]) * r[k] / s2);
        EXPECT_NEAR(g / double(j == 0 ? si.valid : sd.valid), s2, 1e-3 * s2);
      }
    }
  }
  ResidualSet none = sd;
  none.valid = 0;
  none.sum_squares = 0.0;
  EXPECT_EQ(estimate_scales(si, none, n, o, {0.0, 0.0}, kernels, 1)[1], 0.0);
  EXPECT_EQ(estimate_scales(si, none, n, o, {0.0, 0.0}, kernels, 1)[0], estimate_scale(si, n, o, 0.0, kernels, 1));
  o.kind = WeightKind::kHuber;
  const auto huber = estimate_scales(si, sd, n, o, {0.0, 0.0}, kernels, 1);
  EXPECT_EQ(huber[0], estimate_scale(si, n, o, 0.0, kernels, 1));
  EXPECT_EQ(huber[1], estimate_scale(sd, n, o, 0.0, kernels, 1));
}

TEST(RgbdKernels, ResultsAreBitIdenticalForEveryThreadCount) {
  const RgbdLevel& a = scene().reference.pyramid.levels[0];
  const RgbdLevel& b = scene().current.pyramid.levels[0];
  const Eigen::VectorXd x = near_truth();
  RgbdProblemOptions o;
  RgbdOdometryProblem one(a, b, o);
  const auto l1 = one.linearize(x, {});
  const auto f1 = one.evaluate(se3::to_ambient(scene().T_21));
  for (int threads : {2, 3}) {
    o.threads = threads;
    RgbdOdometryProblem many(a, b, o);
    const auto ln = many.linearize(x, {});
    EXPECT_EQ(ln.f1.a, l1.f1.a);
    EXPECT_EQ(ln.f2.a, l1.f2.a);
    EXPECT_EQ((ln.f1.H - l1.f1.H).norm(), 0.0);
    EXPECT_EQ((ln.f2.b - l1.f2.b).norm(), 0.0);
    EXPECT_EQ(many.last_stats().sigma_intensity, one.last_stats().sigma_intensity);
    EXPECT_EQ(many.evaluate(se3::to_ambient(scene().T_21)), f1);
  }
  // The reference terms (rows split over threads: each chunk writes from its counted first index).
  const auto floats = [](const PooledFloats& v) { return std::vector<float>(v.data(), v.data() + v.size()); };
  const ReferenceTerms t1 = make_reference_terms(a, 0.1, 10.0, true, 1);
  for (int threads : {2, 3}) {
    const ReferenceTerms tn = make_reference_terms(a, 0.1, 10.0, true, threads);
    ASSERT_EQ(tn.count, t1.count);
    for (auto member : {&ReferenceTerms::x, &ReferenceTerms::y, &ReferenceTerms::z, &ReferenceTerms::intensity,
                        &ReferenceTerms::gi_u, &ReferenceTerms::gi_v, &ReferenceTerms::gd_u, &ReferenceTerms::gd_v}) {
      EXPECT_EQ(floats(tn.*member), floats(t1.*member));
    }
  }
  // The frame preparation and a whole coarse-to-fine estimate, too.
  const io::RgbdImage im = render_plane(Eigen::Isometry3d::Identity());
  const PreparedFrame p1 = prepare_frame(im, kK, 3, 1), p2 = prepare_frame(im, kK, 3, 2);
  for (int l = 0; l < 3; ++l) EXPECT_EQ(p1.pyramid.levels[l].depth.data, p2.pyramid.levels[l].depth.data);
  EXPECT_EQ(p1.statistics.pi_depth, p2.statistics.pi_depth);
  EXPECT_EQ(p1.statistics.var_intensity, p2.statistics.var_intensity);
  TrackerOptions t;
  t.levels = 3;
  t.method = "bounded";
  const PairResult r1 = estimate_motion(scene().reference, scene().current, Eigen::Isometry3d::Identity(), t);
  t.problem.threads = 2;
  const PairResult r2 = estimate_motion(scene().reference, scene().current, Eigen::Isometry3d::Identity(), t);
  EXPECT_EQ((r1.T_21.matrix() - r2.T_21.matrix()).norm(), 0.0);
  EXPECT_EQ(r1.iterations, r2.iterations);
}

TEST(RgbdKernels, EvaluateAgreesWithTheModelsAndTheWeightedResiduals) {
  RgbdOdometryProblem p(scene().reference.pyramid.levels[1], scene().current.pyramid.levels[1]);
  const Eigen::VectorXd x = near_truth();
  const auto lin = p.linearize(x, {});
  const auto f = p.evaluate(x);
  EXPECT_EQ(f[0], lin.f1.a);  // the same sums in the same order
  EXPECT_EQ(f[1], lin.f2.a);
  // At another x: F = sum w r^2 with the weights of that linearization (double path's r).
  const Eigen::VectorXd x2 = se3::to_ambient(scene().T_21);
  const auto f2 = p.evaluate(x2);
  for (int j : {1, 2}) {
    const solvers::ResidualData d = p.residuals(j, x2, false);
    const double want = d.r.dot(d.w.cwiseProduct(d.r));
    EXPECT_NEAR(f2[j - 1], want, 1e-4 * want) << "objective " << j;
  }
}

TEST(RgbdKernels, OneObjectiveProblemsBuildOnlyF1AndReportTheOtherOnRequest) {
  const RgbdLevel& a = scene().reference.pyramid.levels[1];
  const RgbdLevel& b = scene().current.pyramid.levels[1];
  const Eigen::VectorXd x = near_truth();
  for (const bool depth_first : {false, true}) {
    RgbdProblemOptions o;
    o.depth_first = depth_first;
    RgbdOdometryProblem full(a, b, o);
    o.model_f2 = false;
    RgbdOdometryProblem single(a, b, o);
    const auto lf = full.linearize(x, {}), ls = single.linearize(x, {});
    EXPECT_EQ(ls.f1.a, lf.f1.a);
    EXPECT_EQ((ls.f1.H - lf.f1.H).norm(), 0.0);
    EXPECT_EQ(ls.f2.a, 0.0);
    EXPECT_EQ(ls.f2.H.norm(), 0.0);
    EXPECT_EQ(single.evaluate(x)[1], 0.0);
    // Both objectives with weights estimated at x: those of the two-objective problem (up to
    // the scale's fixed point, which single starts from its own estimate and stops within
    // scale_tolerance = 1e-4 of sigma^2).
    const auto both = single.objectives_at(x);
    EXPECT_NEAR(both[0], full.last_stats().f_intensity, 1e-4 * full.last_stats().f_intensity);
    EXPECT_NEAR(both[1], full.last_stats().f_depth, 1e-4 * full.last_stats().f_depth);
  }
}

TEST(RgbdKernels, PixelMotionIsTheRmsImageMotionOfTheStep) {
  RgbdOdometryProblem p(scene().reference.pyramid.levels[0], scene().current.pyramid.levels[0]);
  const Eigen::VectorXd x = se3::to_ambient(scene().T_21);
  se3::Vector6d d;
  d << 2e-4, -1e-4, 3e-4, 1e-4, 2e-4, -1.5e-4;
  // Every reference point projected at x and at exp(d) x.
  const RgbdLevel& ref = scene().reference.pyramid.levels[0];
  const Eigen::Isometry3d T = scene().T_21, Td = se3::exp(d) * scene().T_21;
  double sum2 = 0.0;
  int n = 0;
  for (int v = 0; v < ref.depth.height; ++v) {
    for (int u = 0; u < ref.depth.width; ++u) {
      const double z = ref.depth.at(u, v);
      if (!(z >= 0.1 && z <= 10.0)) continue;
      const Eigen::Vector3d P((u - kK.cx) / kK.fx * z, (v - kK.cy) / kK.fy * z, z);
      const Eigen::Vector3d q = T * P, qd = Td * P;
      const Eigen::Vector2d y(kK.fx * q.x() / q.z(), kK.fy * q.y() / q.z());
      const Eigen::Vector2d yd(kK.fx * qd.x() / qd.z(), kK.fy * qd.y() / qd.z());
      sum2 += (yd - y).squaredNorm();
      ++n;
    }
  }
  const double rms = std::sqrt(sum2 / n);
  EXPECT_GT(rms, 0.05);
  EXPECT_NEAR(p.pixel_motion(x, d), rms, 0.02 * rms);  // first order, a sample of the terms
  EXPECT_NEAR(p.pixel_motion(x, 2.0 * d), 2.0 * p.pixel_motion(x, d), 1e-9);
}

TEST(RgbdKernels, AStepBelowThePixelToleranceIsNotTaken) {
  RgbdOdometryProblem p(scene().reference.pyramid.levels[1], scene().current.pyramid.levels[1]);
  const Eigen::VectorXd x0 = se3::to_ambient(Eigen::Isometry3d::Identity());
  solvers::SolverOptions o;
  o.max_iterations = 10;
  o.step_measure = [&p](const Eigen::VectorXd& at, const Eigen::VectorXd& d) { return p.pixel_motion(at, d); };
  o.step_measure_tolerance = 1e9;  // every step is "too small to see"
  Eigen::VectorXd x = x0;
  const solvers::Summary s = solvers::solve(p, solvers::WeightedSum(0.0), "gn", x, o);
  EXPECT_EQ(s.iterations, 1);
  EXPECT_EQ(s.termination, solvers::TerminationReason::kStepTolerance);
  EXPECT_EQ(x, x0);
  EXPECT_EQ(s.final_f1, s.initial_f1);
  // A realistic tolerance stops after steps were taken, near the truth.
  o.step_measure_tolerance = 0.05;
  o.step_tolerance = 0.0;
  o.relative_decrease_tolerance = 0.0;
  const solvers::Summary t = solvers::solve(p, solvers::WeightedSum(0.0), "gn", x, o);
  EXPECT_EQ(t.termination, solvers::TerminationReason::kStepTolerance);
  EXPECT_GT(t.iterations, 2);
  EXPECT_LT(se3::log(se3::from_ambient(x) * scene().T_21.inverse()).norm(), 2e-3);
}

TEST(RgbdKernels, EveryJacobianKindRecoversTheMotion) {
  for (const JacobianKind kind : {JacobianKind::kForward, JacobianKind::kInverse, JacobianKind::kEsm}) {
    SCOPED_TRACE(to_string(kind));
    TrackerOptions t;
    t.levels = 3;
    t.method = "weighted";
    t.problem.jacobian = kind;
    const PairResult r = estimate_motion(scene().reference, scene().current, Eigen::Isometry3d::Identity(), t);
    const se3::Vector6d e = se3::log(r.T_21 * scene().T_21.inverse());
    EXPECT_LT(e.head<3>().norm(), 1e-3);  // m
    EXPECT_LT(e.tail<3>().norm(), 1e-3);  // rad
  }
  EXPECT_EQ(parse_jacobian_kind("esm"), JacobianKind::kEsm);
  EXPECT_THROW(parse_jacobian_kind("newton"), Error);
}

// "auto" (the tracker's default) is each method's own kind: inverse for joint, inverse and then
// forward at the finest level for robust, forward for the others; an explicit request wins; a
// problem refuses the unresolved name.
TEST(RgbdKernels, AutoJacobianIsTheMethodsOwnKind) {
  EXPECT_EQ(TrackerOptions{}.problem.jacobian, JacobianKind::kMethodDefault);
  EXPECT_EQ(parse_jacobian_kind("auto"), JacobianKind::kMethodDefault);
  EXPECT_EQ(method_jacobian(Method::kJoint, JacobianKind::kMethodDefault), JacobianKind::kInverse);
  for (const Method m :
       {Method::kSingle, Method::kDepth, Method::kWeighted, Method::kBounded, Method::kScaled, Method::kNoiseBounded}) {
    EXPECT_EQ(method_jacobian(m, JacobianKind::kMethodDefault), JacobianKind::kForward) << to_string(m);
  }
  EXPECT_EQ(method_jacobian(Method::kJoint, JacobianKind::kMethodDefault, true), JacobianKind::kInverse);
  // robust: reference-side gradients at the coarser levels, exact ones at the finest.
  EXPECT_EQ(method_jacobian(Method::kRobust, JacobianKind::kMethodDefault), JacobianKind::kInverse);
  EXPECT_EQ(method_jacobian(Method::kRobust, JacobianKind::kMethodDefault, true), JacobianKind::kForward);
  EXPECT_EQ(method_jacobian(Method::kRobust, JacobianKind::kInverse, true), JacobianKind::kInverse);
  EXPECT_EQ(method_jacobian(Method::kJoint, JacobianKind::kForward), JacobianKind::kForward);
  EXPECT_EQ(method_jacobian(Method::kSingle, JacobianKind::kEsm), JacobianKind::kEsm);
  RgbdProblemOptions unresolved;
  unresolved.jacobian = JacobianKind::kMethodDefault;
  EXPECT_THROW(RgbdOdometryProblem(scene().reference.pyramid.levels[0], scene().current.pyramid.levels[0], unresolved),
               Error);
  // The tracker resolves it: joint under "auto" is joint under "inverse", bit for bit.
  TrackerOptions a;
  a.levels = 3;
  a.method = "joint";
  TrackerOptions b = a;
  b.problem.jacobian = JacobianKind::kInverse;
  const PairResult ra = estimate_motion(scene().reference, scene().current, Eigen::Isometry3d::Identity(), a);
  const PairResult rb = estimate_motion(scene().reference, scene().current, Eigen::Isometry3d::Identity(), b);
  EXPECT_TRUE(ra.T_21.matrix() == rb.T_21.matrix());
}

// The problems' buffers come from a per-thread pool and are not initialized
// (odometry/kernels/pooled_floats.h): fill the pool with NaN-filled blocks, and every result must
// still equal, bit for bit, that of a problem built before (a read of an unwritten entry
// would give NaN or another number).
TEST(RgbdKernels, PooledBuffersHoldingOtherNumbersDoNotChangeResults) {
  const RgbdLevel& a = scene().reference.pyramid.levels[0];
  const RgbdLevel& b = scene().current.pyramid.levels[0];
  const Eigen::VectorXd x = near_truth(), x2 = se3::to_ambient(scene().T_21);
  for (bool joint : {false, true}) {
    for (bool model_f2 : {true, false}) {
      RgbdProblemOptions o;
      o.joint_weights = joint;
      o.model_f2 = model_f2 || joint;
      solvers::Linearization before;
      std::array<double, 2> f_before{};
      std::size_t smallest = 0;  // the smallest array the problem asks for
      {
        RgbdOdometryProblem p(a, b, o);
        before = p.linearize(x, {});
        f_before = p.evaluate(x2);
        smallest = padded_terms(static_cast<std::size_t>(p.num_terms()));
      }
      {
        // Taking 48 arrays of that size takes every pooled block the problem could use
        // (the pool hands out the smallest block that fits); all of them now hold NaN.
        std::vector<PooledFloats> junk;
        for (int i = 0; i < 48; ++i) {
          junk.emplace_back(smallest);
          std::fill(junk.back().data(), junk.back().data() + junk.back().size(), std::nanf(""));
        }
      }  // released: the next problem takes these blocks
      EXPECT_GE(PooledFloats::pooled_blocks(), 48u);
      RgbdOdometryProblem p(a, b, o);
      const solvers::Linearization after = p.linearize(x, {});
      EXPECT_EQ(after.f1.a, before.f1.a);
      EXPECT_EQ(after.f2.a, before.f2.a);
      EXPECT_EQ((after.f1.H - before.f1.H).norm(), 0.0);
      EXPECT_EQ((after.f1.b - before.f1.b).norm(), 0.0);
      EXPECT_EQ((after.f2.H - before.f2.H).norm(), 0.0);
      EXPECT_EQ((after.f2.b - before.f2.b).norm(), 0.0);
      const std::array<double, 2> f_after = p.evaluate(x2);
      EXPECT_EQ(f_after[0], f_before[0]);
      EXPECT_EQ(f_after[1], f_before[1]);
    }
  }
}
