#include "harnesses.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "experiments/conic_files/cbf_file.h"
#include "experiments/conic_files/conic_file.h"
#include "odometry/io/input_limits.h"
#include "odometry/io/metrics.h"
#include "odometry/io/png_io.h"
#include "odometry/io/pose_error.h"
#include "odometry/io/trajectory.h"
#include "odometry/io/tum_dataset.h"
#include "solvers/conic/cones.h"
#include "solvers/error.h"

namespace bivo::fuzz {
namespace {

namespace fs = std::filesystem;

// The readers take paths: each input goes to one scratch file per process (in memory when
// /dev/shm exists), removed at exit.
class Scratch {
 public:
  explicit Scratch(const char* suffix) {
    const std::string dir = fs::is_directory("/dev/shm") ? "/dev/shm" : fs::temp_directory_path().string();
    path_ = dir + "/bivo_fuzz_" + std::to_string(::getpid()) + suffix;
  }
  ~Scratch() { std::remove(path_.c_str()); }
  const std::string& write(const std::uint8_t* data, std::size_t size) {
    std::ofstream(path_, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data), size);
    return path_;
  }

 private:
  std::string path_;
};

// Limits small enough that one input cannot make a run slow, large enough for every seed.
void set_fuzz_limits() {
  odometry::io::input_limits().max_image_pixels = 1 << 20;
  odometry::io::input_limits().max_list_entries = 100000;
  experiments::max_cbf_size() = 100000;
}

template <typename F>
void rejecting_with_error(F&& f) {
  try {
    f();
  } catch (const Error&) {
  }
}

}  // namespace

void tum_list(const std::uint8_t* data, std::size_t size) {
  static Scratch scratch(".txt");
  set_fuzz_limits();
  const std::string& path = scratch.write(data, size);
  rejecting_with_error([&] {
    const auto list = odometry::io::read_file_list(path);
    // Associate the list with itself shifted by a few milliseconds and with a huge window.
    std::vector<odometry::io::ListedFile> shifted = list;
    for (auto& f : shifted) f.timestamp += 0.004;
    odometry::io::associate_lists(list, shifted, "/seq", 0.02);
    odometry::io::associate_lists(list, list, "/seq", 1e300);
  });
  rejecting_with_error([&] { odometry::io::read_associations(path, "/seq", 0.02); });
}

void trajectory(const std::uint8_t* data, std::size_t size) {
  static Scratch scratch(".txt");
  set_fuzz_limits();
  const std::string& path = scratch.write(data, size);
  rejecting_with_error([&] {
    const odometry::io::Trajectory t = odometry::io::read_tum_trajectory(path);
    const double t0 = t.front().timestamp, t1 = t.back().timestamp;
    odometry::io::nearest_pose(t, 0.5 * (t0 + t1), 0.1);
    odometry::io::interpolate_pose(t, 0.5 * (t0 + t1));
    odometry::io::groundtruth_motion(t, t0, t1);
    rejecting_with_error([&] { odometry::io::relative_pose_error(t, t); });
    rejecting_with_error([&] { odometry::io::absolute_trajectory_error(t, t); });
  });
}

void png(const std::uint8_t* data, std::size_t size) {
  static Scratch scratch(".png");
  set_fuzz_limits();
  const std::string& path = scratch.write(data, size);
  rejecting_with_error([&] { odometry::io::read_png8(path); });
  rejecting_with_error([&] { odometry::io::read_png16(path); });
}

void conic_json(const std::uint8_t* data, std::size_t size) {
  static Scratch scratch(".json");
  const std::string& path = scratch.write(data, size);
  rejecting_with_error([&] {
    const solvers::conic::ConicProblem p = experiments::read_conic_json(path);
    const solvers::conic::ConeProduct cones(p.cones);
    (void)cones;
  });
}

void cbf(const std::uint8_t* data, std::size_t size) {
  set_fuzz_limits();
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  rejecting_with_error([&] {
    const experiments::CbfProblem p = experiments::parse_cbf(in, "fuzz.cbf");
    const solvers::conic::ConeProduct cones(p.problem.cones);
    (void)p.file_objective(1.0);
  });
}

const std::vector<Harness>& harnesses() {
  static const std::vector<Harness> all = {
      {"tum_list", tum_list}, {"trajectory", trajectory}, {"png", png}, {"conic_json", conic_json}, {"cbf", cbf}};
  return all;
}

}  // namespace bivo::fuzz
