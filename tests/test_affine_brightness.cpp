// The brightness model (RgbdProblemOptions::affine_brightness): r_I = I_2(y) - (a I_1(x) + b)
// with (a, b) refit at every weight stage, against a pair whose current image is the reference
// scene's brightened by a known gain and offset (closed form), the double path, and the methods'
// defaults; with its radial term (2), against a pair whose images share a known fall-off.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "odometry/affine_brightness.h"
#include "odometry/odometry_methods.h"
#include "odometry/reference_terms.h"
#include "odometry/rgbd_problem.h"
#include "odometry/tracker.h"
#include "solvers/error.h"
#include "tests/support/plane_scene.h"

using namespace bivo;
using namespace bivo::odometry;
namespace se3 = bivo::solvers::se3;
using bivo::testing::camera2;
using bivo::testing::kK;
using bivo::testing::near_truth;
using bivo::testing::rel;
using bivo::testing::render_plane;
using bivo::testing::scene;
using bivo::testing::vignette;

namespace {

constexpr double kGain = 1.08, kOffset = -6.0;

// The plane scene's pair with the current image brightened: I_2 = kGain I + kOffset.
struct BrightenedScene {
  PreparedFrame reference, current;
  Eigen::Isometry3d T_21;
  BrightenedScene() {
    io::RgbdImage second = render_plane(camera2());
    for (float& i : second.intensity) i = static_cast<float>(kGain * i + kOffset);
    reference = prepare_frame(render_plane(Eigen::Isometry3d::Identity()), kK, 3);
    current = prepare_frame(second, kK, 3);
    T_21 = camera2().inverse();
  }
};

const BrightenedScene& brightened() {
  static const BrightenedScene s;
  return s;
}

// The plane scene's pair, both images with the fall-off 1 - kFallOff rho^2 (11 % at the
// corners): I_2(y) = I_1(x) (1 - k rho_y^2) / (1 - k rho_x^2) at the true motion, c ~ -k.
constexpr double kFallOff = 0.2;
struct VignettedScene {
  PreparedFrame reference, current;
  Eigen::Isometry3d T_21;
  VignettedScene() {
    io::RgbdImage first = render_plane(Eigen::Isometry3d::Identity()), second = render_plane(camera2());
    vignette(first, kFallOff);
    vignette(second, kFallOff);
    reference = prepare_frame(first, kK, 3);
    current = prepare_frame(second, kK, 3);
    T_21 = camera2().inverse();
  }
};

const VignettedScene& vignetted() {
  static const VignettedScene s;
  return s;
}

// body(isa) under every instruction set's kernels this CPU runs.
template <class Body>
void for_each_kernel_isa(const Body& body) {
  for (const KernelIsa isa : {KernelIsa::kScalar, KernelIsa::kAvx2, KernelIsa::kAvx512Vl, KernelIsa::kAvx512}) {
    if (!kernels_available(isa)) continue;
    SCOPED_TRACE(to_string(isa));
    body(isa);
  }
}

// p linearized at x (one weight stage: the brightness fit) with the kernels of isa.
void linearize_with(RgbdOdometryProblem& p, KernelIsa isa, const Eigen::VectorXd& x) {
  p.set_kernel_isa(isa);
  p.linearize(x, {});
}

RgbdProblemOptions unit_weights(int affine) {
  RgbdProblemOptions o;
  o.weights.kind = WeightKind::kNone;
  o.affine_brightness = affine;
  o.radial_prior = 0.0;  // c as the data fit it (the ridge: its own test)
  return o;
}

}  // namespace

// At the true motion the brightened image is a I_1 + b up to interpolation: the first weight
// stage recovers (a, b) with every instruction set's kernels, and r_I is what it is on the
// unbrightened pair.
TEST(AffineBrightness, RecoversTheGainAndOffsetAtTheTrueMotion) {
  const BrightenedScene& s = brightened();
  const RgbdLevel& a = s.reference.pyramid.levels[0];
  const RgbdLevel& b = s.current.pyramid.levels[0];
  const Eigen::VectorXd x = se3::to_ambient(s.T_21);
  for_each_kernel_isa([&](KernelIsa isa) {
    RgbdOdometryProblem fitted(a, b, unit_weights(1)), plain(a, b, unit_weights(0));
    linearize_with(fitted, isa, x);
    linearize_with(plain, isa, x);
    EXPECT_NEAR(fitted.last_stats().brightness_gain, kGain, 2e-3);
    EXPECT_NEAR(fitted.last_stats().brightness_offset, kOffset, 0.3);
    EXPECT_EQ(plain.last_stats().brightness_gain, 1.0);
    EXPECT_EQ(plain.last_stats().brightness_offset, 0.0);
    // Without the fit F_I holds the brightness change, (a - 1) I + b, about 5 gray levels per term.
    const double f_fitted = fitted.evaluate(x)[0], f_plain = plain.evaluate(x)[0];
    EXPECT_LT(f_fitted, 1e-2 * f_plain);
    EXPECT_GT(f_plain, 9.0 * fitted.last_stats().valid_intensity);
  });
}

// The float kernels and the double path (residuals(), full data) apply the same (a, b).
TEST(AffineBrightness, FloatModelsMatchTheDoublePath) {
  const BrightenedScene& s = brightened();
  RgbdProblemOptions o;
  o.affine_brightness = 1;
  RgbdOdometryProblem p(s.reference.pyramid.levels[0], s.current.pyramid.levels[0], o);
  solvers::LinearizeOptions full;
  full.want_full = true;
  const Eigen::VectorXd x = near_truth();  // the same motion as the plane scene's
  const solvers::Linearization lin = p.linearize(x, full);
  ASSERT_NE(p.last_stats().brightness_gain, 1.0);
  const solvers::QuadraticModel want = solvers::quadratic_model_of(*lin.full1);
  EXPECT_LT(std::abs(lin.f1.a - want.a), 2e-4 * want.a);
  EXPECT_LT(rel(lin.f1.b, want.b), 2e-4);
  EXPECT_LT(rel(lin.f1.H, want.H), 2e-4);
}

// At the true motion the radial term takes the shared fall-off: c ~ -k (to first order in k),
// a ~ 1, and F_I falls to what the unvignetted pair leaves under (a, b) alone, with every
// instruction set's kernels.
TEST(AffineBrightness, RadialTermRecoversTheFallOffAtTheTrueMotion) {
  const RgbdLevel& a = vignetted().reference.pyramid.levels[0];
  const RgbdLevel& b = vignetted().current.pyramid.levels[0];
  const Eigen::VectorXd x = se3::to_ambient(vignetted().T_21);
  RgbdOdometryProblem clean(scene().reference.pyramid.levels[0], scene().current.pyramid.levels[0], unit_weights(1));
  clean.linearize(x, {});
  const double f_clean = clean.evaluate(x)[0];
  for_each_kernel_isa([&](KernelIsa isa) {
    RgbdOdometryProblem radial(a, b, unit_weights(2)), affine(a, b, unit_weights(1));
    linearize_with(radial, isa, x);
    linearize_with(affine, isa, x);
    EXPECT_NEAR(radial.last_stats().brightness_radial, -kFallOff, 0.02);
    EXPECT_NEAR(radial.last_stats().brightness_gain, 1.0, 5e-3);
    EXPECT_EQ(affine.last_stats().brightness_radial, 0.0);
    const double f_radial = radial.evaluate(x)[0], f_affine = affine.evaluate(x)[0];
    std::printf("[ radial ] F_I at the truth: %.4g radial, %.4g affine, %.4g unvignetted\n", f_radial, f_affine,
                f_clean);
    EXPECT_LT(f_radial, 1.5 * f_clean);
    EXPECT_GT(f_affine, 3.0 * f_radial);
  });
}

// At the identity (q = 0: no motion shows no fall-off) the radial term is not fitted, by the
// kernels of every instruction set.
TEST(AffineBrightness, RadialTermIsLeftAtZeroWhereItCannotBeSeen) {
  for_each_kernel_isa([](KernelIsa isa) {
    const RgbdLevel& level = vignetted().reference.pyramid.levels[0];
    RgbdOdometryProblem p(level, level, unit_weights(2));
    linearize_with(p, isa, se3::to_ambient(Eigen::Isometry3d::Identity()));
    EXPECT_EQ(p.last_stats().brightness_radial, 0.0);
    EXPECT_NEAR(p.last_stats().brightness_gain, 1.0, 1e-6);
  });
}

// rho^2 = (x^2 + y^2) / z^2 of every reference term (the closed form in double), padding 0; the
// vector instruction sets bit for bit alike (division and fused sum are exact per lane).
TEST(AffineBrightness, SquaredRadiiOfTheReferenceTerms) {
  const ReferenceTerms terms = make_reference_terms(vignetted().reference.pyramid.levels[0], 0.1, 10.0, false);
  const std::size_t padded = padded_terms(terms.count);
  ASSERT_GT(terms.count, 1000u);
  PooledFloats vector_isa;
  for_each_kernel_isa([&](KernelIsa isa) {
    const PooledFloats rho2 = squared_radii(kernels(isa), terms.view(), padded);
    double worst = 0.0;
    for (std::size_t k = 0; k < terms.count; ++k) {
      const double z = terms.z[k], xn = terms.x[k] / z, yn = terms.y[k] / z;
      worst = std::max(worst, std::fabs(rho2[k] - (xn * xn + yn * yn)) / (xn * xn + yn * yn + 1e-3));
    }
    EXPECT_LT(worst, 1e-6);
    for (std::size_t k = terms.count; k < padded; ++k) EXPECT_EQ(rho2[k], 0.0f) << k;
    if (isa == KernelIsa::kScalar) return;
    if (vector_isa.empty()) {
      vector_isa = PooledFloats(padded);
      for (std::size_t k = 0; k < padded; ++k) vector_isa[k] = rho2[k];
    }
    for (std::size_t k = 0; k < padded; ++k) ASSERT_EQ(rho2[k], vector_isa[k]) << k;
  });
}

// The ridge on c (radial_prior): the fit of sums built from r = 2 x + 3 + 0.5 q recovers
// (2, 3 - 2 centre, 0.5) without it; with it, q orthogonal to (x, 1), the closed form of the
// ridge c_0 + dc = (sum w q r + c_0 sum w q^2) / (sum w q^2 + gamma sum w) from the present
// c_0; a huge gamma pins c at 0.
TEST(AffineBrightness, RadialPriorIsARidgeTowardNoFallOff) {
  BrightnessSums s;
  const double xs[4] = {-1.0, 1.0, -1.0, 1.0}, qs[4] = {-1.0, -1.0, 1.0, 1.0};  // x, q, 1 orthogonal
  for (int k = 0; k < 4; ++k) {
    const double x = xs[k], q = qs[k], r = 2.0 * x + 3.0 + 0.5 * q;
    s.w += 1.0;
    s.wx += x;
    s.wxx += x * x;
    s.wr += r;
    s.wxr += x * r;
    s.wq += q;
    s.wxq += x * q;
    s.wqq += q * q;
    s.wqr += q * r;
  }
  const BrightnessCorrection free = solve_brightness(s, true);
  ASSERT_TRUE(free.valid);
  EXPECT_NEAR(free.gain, 2.0, 1e-12);
  EXPECT_NEAR(free.offset, 3.0 - 2.0 * kBrightnessCentre, 1e-9);
  EXPECT_NEAR(free.radial, 0.5, 1e-12);
  EXPECT_EQ(solve_brightness(s, false).radial, 0.0);
  const double gamma = 3.0, c0 = -0.2;  // present c: the step is toward the ridge's optimum
  const BrightnessCorrection ridge = solve_brightness(s, true, {gamma, c0});
  EXPECT_NEAR(c0 + ridge.radial, (s.wqr + c0 * s.wqq) / (s.wqq + gamma * s.w), 1e-12);
  EXPECT_NEAR(ridge.gain, 2.0, 1e-12);  // q orthogonal to (x, 1): (a, b) unchanged
  EXPECT_NEAR(c0 + solve_brightness(s, true, {1e12, c0}).radial, 0.0, 1e-9);
}

// The float kernels and the double path apply the same radial term, in r_I and its Jacobian.
TEST(AffineBrightness, RadialFloatModelsMatchTheDoublePath) {
  RgbdProblemOptions o;
  o.affine_brightness = 2;
  o.radial_prior = 0.0;
  RgbdOdometryProblem p(vignetted().reference.pyramid.levels[0], vignetted().current.pyramid.levels[0], o);
  solvers::LinearizeOptions full;
  full.want_full = true;
  const Eigen::VectorXd x = near_truth();
  const solvers::Linearization lin = p.linearize(x, full);
  ASSERT_LT(p.last_stats().brightness_radial, -0.03);  // near, not at, the truth: less than k
  const solvers::QuadraticModel want = solvers::quadratic_model_of(*lin.full1);
  EXPECT_LT(std::abs(lin.f1.a - want.a), 2e-4 * want.a);
  EXPECT_LT(rel(lin.f1.b, want.b), 2e-4);
  EXPECT_LT(rel(lin.f1.H, want.H), 2e-4);
}

// A bi-objective method with the brightness fit finds the motion on the brightened pair as on
// the unbrightened one; without it the brightness change pulls the estimate away. F_I alone
// (single) does not fit it: on a smooth image a brightness change is indistinguishable from motion.
TEST(AffineBrightness, TrackerFindsTheMotionDespiteTheBrightnessChange) {
  const BrightenedScene& s = brightened();
  const auto error_of = [&](const std::string& method, int affine) {
    TrackerOptions o;
    o.method = method;
    o.levels = 3;
    o.problem.affine_brightness = affine;
    const PairResult r = estimate_motion(s.reference, s.current, Eigen::Isometry3d::Identity(), o);
    const Eigen::Isometry3d E = s.T_21.inverse() * r.T_21;
    return E.translation().norm();
  };
  const double fitted = error_of("fixed", 1), plain = error_of("fixed", 0);
  EXPECT_LT(fitted, 1e-4);  // m; the pair moves 2.1 cm
  EXPECT_GT(plain, 1e-3);
  EXPECT_EQ(error_of("single", 1), error_of("single", 0));
}

// A current image without contrast (black): a gain of 0 would explain every r_I away and leave
// no residual scale to weigh them by (joint's weights would be NaN). The fit is refused
// (kMinBrightnessGain) and the linearization stays finite. (The tracker does not solve such a
// pair: FramesWithoutInformation.AnImageWithoutContrastFallsBackToTheMotionPrior.)
TEST(AffineBrightness, ACurrentImageWithoutContrastIsNoBrightnessChange) {
  io::RgbdImage black = render_plane(camera2());
  for (float& i : black.intensity) i = 0.0f;
  const PreparedFrame reference = prepare_frame(render_plane(Eigen::Isometry3d::Identity()), kK, 3);
  const PreparedFrame current = prepare_frame(black, kK, 3);
  const Eigen::VectorXd x = se3::to_ambient(camera2().inverse());
  for (const int affine : {1, 2}) {
    RgbdProblemOptions o;
    o.affine_brightness = affine;
    o.joint_weights = true;
    RgbdOdometryProblem p(reference.pyramid.levels[0], current.pyramid.levels[0], o);
    const solvers::Linearization lin = p.linearize(x, {});
    EXPECT_EQ(p.last_stats().brightness_gain, 1.0) << affine;
    EXPECT_TRUE(std::isfinite(lin.f1.a) && lin.f1.H.allFinite() && lin.f2.H.allFinite()) << affine;
  }
}

// On the vignetted pair the radial term brings the estimate back to the unvignetted pair's.
TEST(AffineBrightness, TrackerWithTheRadialTermFindsTheMotionDespiteTheFallOff) {
  const auto error_of = [&](const std::string& method, int affine, bool vignetting) {
    TrackerOptions o;
    o.method = method;
    o.levels = 3;
    o.problem.affine_brightness = affine;
    const PreparedFrame& a = vignetting ? vignetted().reference : scene().reference;
    const PreparedFrame& b = vignetting ? vignetted().current : scene().current;
    const PairResult r = estimate_motion(a, b, Eigen::Isometry3d::Identity(), o);
    const Eigen::Isometry3d E = vignetted().T_21.inverse() * r.T_21;
    return E.translation().norm();
  };
  for (const std::string method : {"fixed", "joint"}) {
    const double radial = error_of(method, 2, true), affine = error_of(method, 1, true);
    const double clean = error_of(method, 1, false);
    std::printf("[ radial ] %s translation error: %.3g radial, %.3g affine, %.3g unvignetted (m)\n", method.c_str(),
                radial, affine, clean);
    EXPECT_LT(radial, 1e-4) << method;
  }
}

TEST(AffineBrightness, AutoIsRadialForJointAffineForRobustAndTheProblemNeedsItResolved) {
  for (const std::string& m : method_names()) {
    const Method method = parse_method(m);
    EXPECT_EQ(method_affine_brightness(method, -1), method == Method::kJoint    ? 2
                                                    : method == Method::kRobust ? 1
                                                                                : 0)
        << m;
    EXPECT_EQ(method_affine_brightness(method, 0), 0) << m;  // a request is kept
    EXPECT_EQ(method_affine_brightness(method, 1), 1) << m;
    EXPECT_EQ(method_affine_brightness(method, 2), 2) << m;
  }
  const BrightenedScene& s = brightened();
  for (const int bad : {-1, 3}) {
    EXPECT_THROW(RgbdOdometryProblem(s.reference.pyramid.levels[0], s.current.pyramid.levels[0], unit_weights(bad)),
                 Error)
        << bad;
  }
  for (const double bad : {-1.0, std::numeric_limits<double>::infinity(), std::nan("")}) {
    RgbdProblemOptions o = unit_weights(2);
    o.radial_prior = bad;
    EXPECT_THROW(RgbdOdometryProblem(s.reference.pyramid.levels[0], s.current.pyramid.levels[0], o), Error) << bad;
  }
}
