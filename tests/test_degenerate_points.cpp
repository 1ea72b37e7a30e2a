// A point where the objectives measure nothing is never reported as a solution, by any
// backend. First on a toy problem whose terms vanish outside a window (so F_1 = F_2 = 0
// there, the global "minimum"), then on real fr1/rpy frame pairs, where a long step of a
// whole-problem backend can warp every pixel out of the image: each backend's pose is checked
// against `exact` (epsilon-constraint backends) or `gn` (weighted-sum ones), or its failure
// must be reported.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include <gtest/gtest.h>

#include "odometry/io/pose_error.h"
#include "odometry/tracker.h"
#include "solvers/backend_registry.h"
#include "solvers/geometry/se3.h"
#include "solvers/outer_loop.h"

using namespace bivo;

namespace {

// Three terms per objective, r = x - a_j, valid only while |x| < 10: outside, every term drops
// out and F_1 = F_2 = 0. The valid optimum of either objective is at the window's edge.
class WindowProblem final : public solvers::BiObjectiveProblem {
 public:
  std::string name() const override { return "window"; }
  const solvers::Manifold& manifold() const override { return manifold_; }
  solvers::Linearization linearize(const Eigen::VectorXd& x, const solvers::LinearizeOptions& o) override {
    return solvers::linearize_from_residuals(*this, x, o);
  }
  std::array<double, 2> evaluate(const Eigen::VectorXd& x) override {
    const auto f = [&](int j) {
      const solvers::ResidualData d = residuals(j, x, false);
      return d.r.dot(d.w.cwiseProduct(d.r));
    };
    return {f(1), f(2)};
  }
  solvers::ResidualData residuals(int j, const Eigen::VectorXd& x, bool with_jacobian) override {
    const bool valid = std::abs(x[0]) < 10.0;
    solvers::ResidualData d;
    d.r = Eigen::VectorXd::Constant(3, valid ? x[0] - (j == 1 ? 20.0 : 15.0) : 0.0);
    d.w = Eigen::VectorXd::Ones(3);
    if (with_jacobian) d.J = Eigen::MatrixXd::Constant(3, 1, valid ? 1.0 : 0.0);
    return d;
  }
  std::optional<std::string> degenerate(const Eigen::VectorXd& x) override {
    if (std::abs(x[0]) < 10.0) return std::nullopt;
    return std::string("no term valid");
  }

 private:
  solvers::EuclideanManifold manifold_{1};
};

const std::string kSequence = std::string(BIVO_SHARED_DIR) + "/data/tum/rgbd_dataset_freiburg1_rpy";

}  // namespace

// Every backend: converged only at a valid point; a degenerate end is reported and x reset.
TEST(DegeneratePoints, NoBackendConvergesWhereNothingIsMeasured) {
  for (const solvers::BackendInfo& info : solvers::backend_infos()) {
    for (const bool weighted : {true, false}) {
      if (weighted ? !info.weighted_sum : !info.epsilon_constraint) continue;
      WindowProblem problem;
      Eigen::VectorXd x = Eigen::VectorXd::Zero(1);
      // F_2(0) = 675: the bound 300 asks for x > 5 (the valid part of the window) and is met
      // for free outside it.
      const solvers::Summary s = weighted ? solvers::solve(problem, solvers::WeightedSum(0.5), info.name, x)
                                          : solvers::solve(problem, solvers::EpsilonConstraint(300.0), info.name, x);
      const std::string what = info.name + (weighted ? " (weighted sum)" : " (epsilon)");
      std::printf("[ window ] %-22s x = %9.4f  %s: %s\n", what.c_str(), x[0], solvers::to_string(s.termination),
                  s.message.c_str());
      ASSERT_TRUE(x.allFinite()) << what;
      EXPECT_FALSE(problem.degenerate(x)) << what << " ended at x = " << x[0] << ": " << s.message;
      if (s.termination == solvers::TerminationReason::kDegeneratePoint) {
        EXPECT_EQ(x[0], 0.0) << what << ": x goes back to the start";
        EXPECT_FALSE(s.converged());
      }
    }
  }
}

// The default is "every point is valid": problems that do not override it are unaffected.
TEST(DegeneratePoints, DefaultIsNeverDegenerate) {
  class Quadratic final : public solvers::BiObjectiveProblem {
   public:
    std::string name() const override { return "quadratic"; }
    const solvers::Manifold& manifold() const override { return m_; }
    solvers::Linearization linearize(const Eigen::VectorXd& x, const solvers::LinearizeOptions& o) override {
      return solvers::linearize_from_residuals(*this, x, o);
    }
    std::array<double, 2> evaluate(const Eigen::VectorXd& x) override { return {x.squaredNorm(), 0.0}; }
    solvers::ResidualData residuals(int, const Eigen::VectorXd& x, bool) override {
      return {x, {}, Eigen::VectorXd::Ones(1)};
    }
    solvers::EuclideanManifold m_{1};
  } q;
  EXPECT_FALSE(q.degenerate(Eigen::VectorXd::Constant(1, 1e300)));
}

// Real frame pairs of fr1/rpy at 320x240 (finest level 1), one tracker run per backend with
// its scalarization's method (bounded: epsilon-constraint; weighted: weighted sum), checked
// against `exact` / `gn` on the same pair: within 2.5 cm and 1.5 deg of it (ipopt-nlp stops on
// the tracker's budget of 20 Ipopt iterations per level, 1.2 cm off on 1->2; the wrong poses
// below were 26 cm and 2.2 m off), or the pair (or a level) reported failed. Each starts from the previous pair's
// ground-truth motion, as the tracker's constant-velocity prior would; in a 40-frame run ipopt-nlp's poses of the pairs
// 33->34 and 38->39 were 0.26 m and 2.2 m off with 45 % and 22 % of the terms still valid.
TEST(DegeneratePoints, EveryBackendOnRealFramePairs) {
  if (!std::filesystem::exists(kSequence)) GTEST_SKIP() << "shared data absent: " << kSequence;
  for (const int first : {1, 12, 33, 38}) {
    odometry::TrackerOptions o;
    o.finest_level = 1;
    const odometry::FramePair pair = odometry::load_frame_pair(kSequence, first, first + 1, o);
    const odometry::FramePair before = odometry::load_frame_pair(kSequence, first - 1, first, o);
    ASSERT_TRUE(before.groundtruth_T21);
    const Eigen::Isometry3d prior = *before.groundtruth_T21;
    for (const bool weighted : {true, false}) {
      o.method = weighted ? "weighted" : "bounded";
      o.backend = weighted ? "gn" : "exact";
      const odometry::PairResult reference = odometry::estimate_motion(pair.reference, pair.current, prior, o);
      ASSERT_TRUE(reference.valid) << o.backend << " on " << first;
      for (const solvers::BackendInfo& info : solvers::backend_infos()) {
        if (weighted ? !info.weighted_sum : !info.epsilon_constraint) continue;
        o.backend = info.name;
        const odometry::PairResult r = odometry::estimate_motion(pair.reference, pair.current, prior, o);
        const odometry::io::PoseError e = odometry::io::pose_error(r.T_21, reference.T_21);
        bool skipped = false;
        for (const odometry::LevelResult& l : r.levels) skipped = skipped || l.skipped;
        std::printf("[ pair ] %d->%d %-8s %-22s valid %d skipped level %d, %.4f m %.3f deg from %s  %s\n", first,
                    first + 1, o.method.c_str(), info.name.c_str(), r.valid, skipped, e.translation_m, e.rotation_deg,
                    weighted ? "gn" : "exact", r.note.c_str());
        if (!r.valid || skipped) continue;  // a reported failure is an allowed answer
        EXPECT_LT(e.translation_m, 0.025) << info.name << " on " << first << "->" << first + 1;
        EXPECT_LT(e.rotation_deg, 1.5) << info.name << " on " << first << "->" << first + 1;
      }
    }
  }
}

// The direct use of a problem: pair 0->1 at level 2 with a bound of 1 on F_D (18 at the
// start), which leaving the image "meets" with F = 0; ipopt-nlp once returned converged there.
// No backend may end at such a pose.
TEST(DegeneratePoints, TightBoundOnARealPairIsNeverMetByLeavingTheImage) {
  if (!std::filesystem::exists(kSequence)) GTEST_SKIP() << "shared data absent: " << kSequence;
  odometry::TrackerOptions o;
  o.method = "bounded";
  const odometry::FramePair pair = odometry::load_frame_pair(kSequence, 0, 1, o);
  for (const solvers::BackendInfo& info : solvers::backend_infos()) {
    if (!info.epsilon_constraint) continue;
    const std::unique_ptr<odometry::RgbdOdometryProblem> problem = pair.problem(2, o);
    Eigen::VectorXd x = solvers::se3::to_ambient(Eigen::Isometry3d::Identity());
    const solvers::Summary s = solvers::solve(*problem, solvers::EpsilonConstraint(1.0), info.name, x);
    const std::optional<std::string> why = problem->degenerate(x);
    std::printf("[ bound 1 ] %-24s %s: %s; F = (%.4g, %.4g)%s\n", info.name.c_str(), solvers::to_string(s.termination),
                s.message.c_str(), s.final_f1, s.final_f2, why ? (", DEGENERATE: " + *why).c_str() : "");
    EXPECT_FALSE(why) << info.name;
    EXPECT_GT(s.final_f1, 0.0) << info.name << ": F_1 = 0 means nothing was measured";
  }
}
