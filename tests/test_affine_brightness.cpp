// The affine brightness (RgbdProblemOptions::affine_brightness): r_I = I_2(y) - (a I_1(x) + b)
// with (a, b) refit at every weight stage, against a pair whose current image is the reference
// scene's brightened by a known gain and offset (closed form), the double path, and the methods'
// defaults.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "odometry/odometry_methods.h"
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

RgbdProblemOptions unit_weights(int affine) {
  RgbdProblemOptions o;
  o.weights.kind = WeightKind::kNone;
  o.affine_brightness = affine;
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
  for (const KernelIsa isa : {KernelIsa::kScalar, KernelIsa::kAvx2, KernelIsa::kAvx512Vl, KernelIsa::kAvx512}) {
    if (!kernels_available(isa)) continue;
    SCOPED_TRACE(to_string(isa));
    RgbdOdometryProblem fitted(a, b, unit_weights(1)), plain(a, b, unit_weights(0));
    fitted.set_kernel_isa(isa);
    plain.set_kernel_isa(isa);
    fitted.linearize(x, {});
    plain.linearize(x, {});
    EXPECT_NEAR(fitted.last_stats().brightness_gain, kGain, 2e-3);
    EXPECT_NEAR(fitted.last_stats().brightness_offset, kOffset, 0.3);
    EXPECT_EQ(plain.last_stats().brightness_gain, 1.0);
    EXPECT_EQ(plain.last_stats().brightness_offset, 0.0);
    // Without the fit F_I holds the brightness change, (a - 1) I + b, about 5 gray levels per term.
    const double f_fitted = fitted.evaluate(x)[0], f_plain = plain.evaluate(x)[0];
    EXPECT_LT(f_fitted, 1e-2 * f_plain);
    EXPECT_GT(f_plain, 9.0 * fitted.last_stats().valid_intensity);
  }
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

TEST(AffineBrightness, AutoIsOnForJointAndRobustOnlyAndTheProblemNeedsItResolved) {
  for (const std::string& m : method_names()) {
    const Method method = parse_method(m);
    EXPECT_EQ(method_affine_brightness(method, -1), method == Method::kJoint || method == Method::kRobust ? 1 : 0) << m;
    EXPECT_EQ(method_affine_brightness(method, 0), 0) << m;  // a request is kept
    EXPECT_EQ(method_affine_brightness(method, 1), 1) << m;
  }
  const BrightenedScene& s = brightened();
  for (const int bad : {-1, 2}) {
    EXPECT_THROW(RgbdOdometryProblem(s.reference.pyramid.levels[0], s.current.pyramid.levels[0], unit_weights(bad)),
                 Error)
        << bad;
  }
}
