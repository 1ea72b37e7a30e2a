// Foundation checks: SE(3) helpers against closed forms, trajectory I/O round trip and
// its errors, atomic writes.
#include <cstdio>
#include <fstream>

#include <gtest/gtest.h>

#include "odometry/io/atomic_file.h"
#include "odometry/io/trajectory.h"
#include "solvers/error.h"
#include "solvers/geometry/se3.h"

using namespace bivo;
namespace se3 = bivo::solvers::se3;

TEST(Se3, ExpOfPureRotationAboutZIsClosedForm) {
  se3::Vector6d xi = se3::Vector6d::Zero();
  xi(5) = 0.3;
  const Eigen::Isometry3d T = se3::exp(xi);
  EXPECT_NEAR(T.linear()(0, 0), std::cos(0.3), 1e-15);
  EXPECT_NEAR(T.linear()(1, 0), std::sin(0.3), 1e-15);
  EXPECT_NEAR(T.translation().norm(), 0.0, 1e-15);
}

TEST(Se3, LogInvertsExp) {
  se3::Vector6d xi;
  xi << 0.1, -0.2, 0.3, 0.4, -0.1, 0.25;
  EXPECT_LT((se3::log(se3::exp(xi)) - xi).norm(), 1e-12);
  se3::Vector6d tiny = xi * 1e-9;
  EXPECT_LT((se3::log(se3::exp(tiny)) - tiny).norm(), 1e-20);
}

TEST(Se3, ExpTranslationMatchesNumericalIntegration) {
  // exp([v; w]) translation = integral_0^1 exp(s w^) v ds; integrate with Simpson's rule.
  se3::Vector6d xi;
  xi << 0.5, 0.2, -0.1, 0.3, 0.7, -0.4;
  Eigen::Vector3d acc = Eigen::Vector3d::Zero();
  const int n = 2000;
  for (int i = 0; i <= n; ++i) {
    const double s = double(i) / n;
    const double c = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
    acc += c * se3::so3_exp(s * xi.tail<3>()) * xi.head<3>();
  }
  acc /= 3.0 * n;
  EXPECT_LT((se3::exp(xi).translation() - acc).norm(), 1e-12);
}

TEST(Se3, AmbientRoundTrip) {
  se3::Vector6d xi;
  xi << 0.1, 0.2, 0.3, -0.5, 0.1, 0.2;
  const Eigen::Isometry3d T = se3::exp(xi);
  const Eigen::Isometry3d U = se3::from_ambient(se3::to_ambient(T));
  EXPECT_LT((T.matrix() - U.matrix()).norm(), 1e-14);
}

TEST(Trajectory, RoundTripAndNearest) {
  const std::string path = ::testing::TempDir() + "/traj.txt";
  odometry::io::Trajectory t;
  for (int i = 0; i < 5; ++i) {
    se3::Vector6d xi = se3::Vector6d::Constant(0.01 * i);
    t.push_back({100.0 + 0.1 * i, se3::exp(xi)});
  }
  odometry::io::write_tum_trajectory(path, t);
  const auto r = odometry::io::read_tum_trajectory(path);
  ASSERT_EQ(r.size(), t.size());
  for (size_t i = 0; i < t.size(); ++i) {
    EXPECT_NEAR(r[i].timestamp, t[i].timestamp, 1e-6);
    EXPECT_LT((r[i].T_wc.matrix() - t[i].T_wc.matrix()).norm(), 1e-8);
  }
  EXPECT_EQ(odometry::io::nearest_pose(r, 100.21, 0.02), &r[2]);
  EXPECT_EQ(odometry::io::nearest_pose(r, 100.25, 0.02), nullptr);
}

TEST(Trajectory, MalformedLineNamesFileAndLine) {
  const std::string path = ::testing::TempDir() + "/bad.txt";
  std::ofstream(path) << "# header\r\n1.0 0 0 0 0 0 0 1\r\n2.0 0 0 zero 0 0 0 1\n";
  try {
    odometry::io::read_tum_trajectory(path);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.txt:3"), std::string::npos) << e.what();
  }
}

TEST(AtomicFile, FailedWriteLeavesNoFile) {
  const std::string path = ::testing::TempDir() + "/atomic.txt";
  std::remove(path.c_str());
  EXPECT_THROW(odometry::io::write_file_atomically(path,
                                                   [](std::ostream& o) {
                                                     o << "half";
                                                     throw Error("boom");
                                                   }),
               Error);
  EXPECT_FALSE(std::ifstream(path).good());
  EXPECT_THROW(odometry::io::write_file_atomically("/nonexistent-dir/x.txt", [](std::ostream&) {}), Error);
}
