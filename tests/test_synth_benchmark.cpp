// The benchmark set's definition (odometry/synth/benchmark_set.h): eight categories, real
// fr3 motion (the twin's where one exists), texture/notexture pairs sharing motion and
// seed, fixed frames and seed; the command line contract of `bivo synth --benchmark-set`;
// the folder digest. The 300-frame renderings themselves are too slow for ctest
// (docs/synthetic.md shows how they were checked).
#include <sys/types.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "odometry/synth/benchmark_set.h"
#include "solvers/error.h"

namespace fs = std::filesystem;
namespace synth = bivo::odometry::synth;

namespace {

fs::path fresh_dir(const std::string& tag) {
  const fs::path p = fs::temp_directory_path() / ("bivo_test_bench_" + tag + "_" + std::to_string(::getpid()));
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace

TEST(SynthBenchmarkSet, EightCategoriesAlongRealMotionTwinsShareIt) {
  const auto set = synth::benchmark_set();
  ASSERT_EQ(set.size(), 8u);
  std::set<std::string> names;
  for (const auto& b : set) {
    names.insert(b.category.name());
    EXPECT_NE(b.trajectory.find("freiburg3"), std::string::npos) << b.category.name();
    EXPECT_NE(b.trajectory.find("-groundtruth.txt"), std::string::npos) << b.category.name();
    EXPECT_FALSE(b.motion_choice.empty());
    // The fr3 twin's own motion wherever the data has it.
    const std::string own = "rgbd_dataset_freiburg3_" + b.category.name();
    if (b.category.texture && (b.category.structure || b.category.near)) {
      EXPECT_EQ(b.trajectory.rfind(own, 0), 0u) << b.category.name() << " uses " << b.trajectory;
    }
    // Texture twins: the same motion and start, so the pair differs only in albedo.
    synth::SynthCategory twin = b.category;
    twin.texture = !twin.texture;
    const synth::BenchmarkSequence t = synth::benchmark_sequence(twin.name());
    EXPECT_EQ(t.trajectory, b.trajectory) << b.category.name();
    EXPECT_EQ(t.start_offset_s, b.start_offset_s) << b.category.name();
    const synth::SynthOptions o = synth::benchmark_options(b, 3);
    EXPECT_EQ(o.frames, 300);
    EXPECT_EQ(o.seed, synth::kBenchmarkSeed);
    EXPECT_EQ(o.threads, 3);
    EXPECT_EQ(o.category.name(), b.category.name());
    EXPECT_TRUE(o.render.sensor_noise);
  }
  EXPECT_EQ(names.size(), 8u);
  EXPECT_THROW(synth::benchmark_sequence("structure_wood_near"), bivo::Error);
}

TEST(SynthBenchmarkSet, MissingTrajectoryIsNamedBeforeAnythingIsRendered) {
  const fs::path out = fresh_dir("missing");
  try {
    synth::render_benchmark_set((out / "no_such_folder").string(), (out / "set").string());
    ADD_FAILURE() << "no error";
  } catch (const bivo::Error& e) {
    EXPECT_NE(std::string(e.what()).find("no_such_folder"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("-groundtruth.txt"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(out / "set"));
  fs::remove_all(out);
}

TEST(SynthBenchmarkSet, DigestSeesEveryByteAndName) {
  const fs::path a = fresh_dir("digest_a"), b = fresh_dir("digest_b");
  for (const fs::path& d : {a, b}) {
    fs::create_directories(d / "rgb");
    std::ofstream(d / "rgb" / "1.png") << "abc";
    std::ofstream(d / "x.txt") << "hello\n";
  }
  EXPECT_EQ(synth::sequence_digest(a.string()), synth::sequence_digest(b.string()));
  EXPECT_EQ(synth::sequence_digest(a.string()).size(), 16u);
  std::ofstream(b / "x.txt") << "hellp\n";
  const std::string changed = synth::sequence_digest(b.string());
  EXPECT_NE(synth::sequence_digest(a.string()), changed);
  std::ofstream(b / "x.txt") << "hello\n";
  fs::rename(b / "rgb" / "1.png", b / "rgb" / "2.png");  // same bytes, another name
  EXPECT_NE(synth::sequence_digest(a.string()), synth::sequence_digest(b.string()));
  fs::remove_all(a);
  fs::remove_all(b);
}

TEST(SynthBenchmarkSet, CommandLineContract) {
  const fs::path out = fresh_dir("cli");
  const auto fails_with = [&](const std::string& args, const std::string& needle) {
    const fs::path err = out / "stderr.txt";
    const std::string cmd = std::string(BIVO_BINARY) + " synth " + args + " 2> " + err.string() + " >/dev/null";
    EXPECT_NE(std::system(cmd.c_str()), 0) << cmd;
    const std::string text = slurp(err);
    EXPECT_NE(text.find(needle), std::string::npos) << cmd << " -> " << text;
  };
  const std::string o = " --output " + (out / "set").string();
  fails_with("--benchmark-set" + o, "--trajectories");
  fails_with("--benchmark-set --trajectories " + out.string() + " --frames 10" + o, "--frames");
  fails_with("--benchmark-set --trajectories " + out.string() + " --seed 3" + o, "--seed");
  fails_with("--benchmark-set --trajectories " + out.string() + o, "nostructure_texture_near_withloop-groundtruth.txt");
  fails_with("--benchmark-set --trajectories " + out.string() + " --category pyramid_texture_near" + o,
             "pyramid_texture_near");
  fails_with(o.substr(1), "--category");
  EXPECT_FALSE(fs::exists(out / "set"));
  fs::remove_all(out);
}
