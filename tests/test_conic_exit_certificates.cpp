// Every exit of the conic IPM re-checked here, from the returned (x, y, z, s) and the data as
// given, with formulas written independently of the solver (dense Eigen, no equilibration):
//   optimal (strict)    primal residual max(||Ax - b|| / max(1, ||b||), ||Gx + s - h|| / max(1, ||h||)),
//                       dual residual ||A'y + G'z + c|| / max(1, ||c||) and the objective gap
//                       |c'x + h'z + b'y| / (1 + |c'x|) all below 1e-8, s and z in K;
//   optimal (reduced)   the note says which strict tolerance fails;
//   primal infeasible   h'z + b'y = -1, ||A'y + G'z|| below 1e-8, z in K;
//   dual infeasible     c'x = -1, ||A x|| and ||G x + s|| below 1e-8, s in K.
// The problems are the families the other conic tests solve (the same generators and seeds
// as test_conic_ipm's random SOCPs and certificates, the QCQP steps of the step backends in
// both forms, with and without polishing and equilibration) plus the huge-bound examples.
#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "solvers/conic/cones.h"
#include "solvers/conic/ipm_solver.h"
#include "solvers/step/qcqp_socp.h"
#include "tests/support/random_conic.h"
#include "tests/support/synthetic_qcqp.h"

using namespace bivo::solvers::conic;
using namespace bivo::solvers::conic::testing;

namespace {

// Slack for summation order only: the solver certifies at 1e-8 with its own sums.
const double kTol = 1e-8 * (1.0 + 1e-6);

double min_eig(const ConeSpec& cones, const Eigen::VectorXd& u) {
  double e = std::numeric_limits<double>::infinity();
  for (int i = 0; i < cones.nonnegative; ++i) e = std::min(e, u[i]);
  int o = cones.nonnegative;
  for (const int d : cones.soc) {
    e = std::min(e, u[o] - u.segment(o + 1, d - 1).norm());
    o += d;
  }
  return u.size() ? e / (1.0 + u.cwiseAbs().maxCoeff()) : 0.0;
}

struct Tally {
  int optimal = 0, reduced = 0, infeasible = 0, other = 0;
};

// The independent check of one exit; counts it in t.
void check_exit(const ConicProblem& p, const IpmResult& r, const std::string& what, Tally& t) {
  const Eigen::MatrixXd G = p.has_dense_G() ? p.dense_G : Eigen::MatrixXd(p.G);
  const Eigen::MatrixXd A = Eigen::MatrixXd(p.A);
  const bool eq = p.b.size() > 0;
  ASSERT_EQ(r.x.size(), p.c.size()) << what;
  ASSERT_EQ(r.z.size(), p.h.size()) << what;
  ASSERT_TRUE(r.x.allFinite() && r.y.allFinite() && r.z.allFinite() && r.s.allFinite()) << what;
  if (r.status == IpmStatus::kOptimal && r.reduced_accuracy) {
    ++t.reduced;
    EXPECT_FALSE(r.note.empty()) << what << ": a reduced-accuracy exit says which tolerance fails";
    return;
  }
  if (r.status == IpmStatus::kOptimal) {
    ++t.optimal;
    const double pa = eq ? (A * r.x - p.b).norm() / std::max(1.0, p.b.norm()) : 0.0;
    const double pg = (G * r.x + r.s - p.h).norm() / std::max(1.0, p.h.norm());
    Eigen::VectorXd d = G.transpose() * r.z + p.c;
    if (eq) d += A.transpose() * r.y;
    const double cx = p.c.dot(r.x);
    const double gap = std::abs(cx + p.h.dot(r.z) + (eq ? p.b.dot(r.y) : 0.0)) / (1.0 + std::abs(cx));
    EXPECT_LT(std::max(pa, pg), kTol) << what << ": primal residual";
    EXPECT_LT(d.norm() / std::max(1.0, p.c.norm()), kTol) << what << ": dual residual";
    EXPECT_LT(gap, kTol) << what << ": objective gap";
    EXPECT_GE(min_eig(p.cones, r.s), -kTol) << what << ": s outside K";
    EXPECT_GE(min_eig(p.cones, r.z), -kTol) << what << ": z outside K";
    return;
  }
  if (r.status == IpmStatus::kPrimalInfeasible) {
    ++t.infeasible;
    Eigen::VectorXd d = G.transpose() * r.z;
    if (eq) d += A.transpose() * r.y;
    EXPECT_NEAR(p.h.dot(r.z) + (eq ? p.b.dot(r.y) : 0.0), -1.0, 1e-9) << what;
    EXPECT_LT(d.norm(), kTol * std::max(1.0, p.c.norm())) << what;
    EXPECT_GE(min_eig(p.cones, r.z), -kTol) << what;
    return;
  }
  if (r.status == IpmStatus::kDualInfeasible) {
    ++t.infeasible;
    EXPECT_NEAR(p.c.dot(r.x), -1.0, 1e-9) << what;
    if (eq) {
      EXPECT_LT((A * r.x).norm(), kTol * std::max(1.0, p.b.norm())) << what;
    }
    EXPECT_LT((G * r.x + r.s).norm(), kTol * std::max(1.0, p.h.norm())) << what;
    EXPECT_GE(min_eig(p.cones, r.s), -kTol) << what;
    return;
  }
  ++t.other;  // max iterations / numerical trouble claim nothing
}

std::vector<IpmSettings> variants() {
  IpmSettings plain, unscaled, bare;
  plain.polish = false;
  unscaled.equilibration_passes = 0;
  bare.polish = false;
  bare.equilibration_passes = 0;
  return {IpmSettings{}, plain, unscaled, bare};
}

}  // namespace

// test_conic_ipm's 1000 random strictly feasible SOCPs (same generator, same seed), each in
// four settings: every optimum claimed must be one.
TEST(ConicExitCertificates, RandomFeasibleSocps) {
  RandomFeasibleSocps problems(2024);
  Tally t;
  for (int trial = 0; trial < 1000; ++trial) {
    const ConicProblem p = problems.next();
    int v = 0;
    for (const IpmSettings& st : variants()) {
      check_exit(p, solve_conic(p, st), "trial " + std::to_string(trial) + " variant " + std::to_string(v++), t);
    }
  }
  std::printf("random SOCPs: %d optimal, %d reduced accuracy, %d other\n", t.optimal, t.reduced, t.other);
  EXPECT_GE(t.optimal, 3900);  // the family is well posed: nearly every exit is a clean optimum
}

// test_conic_ipm's infeasible and unbounded families (same generators, same seeds).
TEST(ConicExitCertificates, InfeasibleAndUnboundedSocps) {
  Tally t;
  for (const bool dual : {false, true}) {
    std::mt19937 rng(dual ? 6 : 5);
    std::normal_distribution<double> g(0.0, 1.0);
    for (int trial = 0; trial < 100; ++trial) {
      ConicProblem p;
      p.cones = random_cones(rng);
      const ConeProduct K(p.cones);
      const int n = dual ? 2 + trial % 5 : 1 + trial % 6, np = trial % 2;
      Eigen::MatrixXd A = Eigen::MatrixXd(random_sparse(np, n, 1.0, rng));
      Eigen::MatrixXd G = Eigen::MatrixXd(random_sparse(K.dim(), n, dual ? 0.8 : 0.8, rng));
      if (!dual) {
        const Eigen::VectorXd zb = random_interior(K, rng);
        Eigen::VectorXd yb(np), x0(n), h(K.dim());
        for (int i = 0; i < np; ++i) yb[i] = g(rng);
        for (int i = 0; i < n; ++i) x0[i] = g(rng);
        for (int i = 0; i < K.dim(); ++i) h[i] = g(rng);
        G -= zb * (G.transpose() * zb + A.transpose() * yb).transpose() / zb.squaredNorm();
        const Eigen::VectorXd b = A * x0;
        h -= zb * (h.dot(zb) + b.dot(yb) + 1.0) / zb.squaredNorm();
        p.A = A.sparseView();
        p.G = G.sparseView(1.0, 1e-12);
        p.b = b;
        p.h = h;
        const Eigen::VectorXd z1 = random_interior(K, rng);
        p.c = -(G.transpose() * z1);
        if (np) p.c -= A.transpose() * Eigen::VectorXd::NullaryExpr(np, [&]() { return g(rng); });
      } else {
        Eigen::VectorXd d(n), x0(n), c(n);
        for (int i = 0; i < n; ++i) d[i] = g(rng), x0[i] = g(rng), c[i] = g(rng);
        A -= (A * d) * d.transpose() / d.squaredNorm();
        const Eigen::VectorXd kb = random_interior(K, rng);
        G -= (G * d + kb) * d.transpose() / d.squaredNorm();
        c -= d * (c.dot(d) + 1.0) / d.squaredNorm();
        p.A = A.sparseView();
        p.G = G.sparseView(1.0, 0.0);
        p.b = A * x0;
        p.h = G * x0 + random_interior(K, rng);
        p.c = c;
      }
      const IpmResult r = solve_conic(p);
      EXPECT_EQ(r.status, dual ? IpmStatus::kDualInfeasible : IpmStatus::kPrimalInfeasible) << status_text(r);
      check_exit(p, r, std::string(dual ? "unbounded " : "infeasible ") + std::to_string(trial), t);
    }
  }
  EXPECT_EQ(t.infeasible, 200);
}

// The QCQP steps of ipm-full and ipm-compressed (synthetic image-like data in raw units), at
// the step backends' tolerances, polished and not.
TEST(ConicExitCertificates, QcqpStepForms) {
  Tally t;
  for (const std::uint32_t seed : {1u, 2u, 3u, 4u}) {
    for (const double fraction : {0.3, 2.0}) {
      const SyntheticStep step = make_synthetic_step(400 * static_cast<int>(seed), seed, fraction);
      const ConicProblem full = full_qcqp_socp(*step.lin.full1, *step.lin.full2, step.epsilon);
      const ConicProblem compressed =
          compressed_qcqp_socp(factor_from_model(step.lin.f1), factor_from_model(step.lin.f2), step.epsilon);
      for (const IpmSettings& st : {step_ipm_settings(), unpolished_step_ipm_settings()}) {
        const std::string what = "seed " + std::to_string(seed) + (st.polish ? " polished" : " plain");
        check_exit(full, solve_conic(full, st), "full form, " + what, t);
        check_exit(compressed, solve_conic(compressed, st), "compressed form, " + what, t);
      }
    }
  }
  std::printf("QCQP steps: %d optimal, %d reduced accuracy, %d other\n", t.optimal, t.reduced, t.other);
  EXPECT_GE(t.optimal, 24);
}

// The huge-bound examples: every exit, polished or not, presolved or not.
TEST(ConicExitCertificates, HugeBounds) {
  Tally t;
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(6, 3);
  G(0, 1) = 1, G(1, 2) = 1, G(2, 1) = -1;
  G(3, 0) = -1, G(4, 1) = -1, G(5, 2) = -1;
  for (const double B : {1e12, 1e15, 1e18, 1e19, 1e20, 1e30}) {
    ConicProblem p;
    p.c = Eigen::Vector3d(1, 0, 0);
    p.G = G.sparseView();
    p.h.resize(6);
    p.h << 1, B, B, 0, -3, -4;
    p.cones = {3, {3}};
    p.A.resize(0, 3);
    p.b.resize(0);
    for (IpmSettings st : variants()) {
      for (const double infinity : {1e20, std::numeric_limits<double>::infinity()}) {
        st.infinity = infinity;
        const IpmResult r = solve_conic(p, st);
        // Presolved rows are certified on the problem without them (their bound is absent).
        if (r.infinite_rows > 0) continue;
        check_exit(p, r, "bound " + std::to_string(B), t);
      }
    }
  }
  std::printf("huge bounds: %d optimal, %d reduced accuracy, %d other\n", t.optimal, t.reduced, t.other);
}
