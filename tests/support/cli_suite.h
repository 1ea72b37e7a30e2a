#pragma once
// The fixture of the tests that run the built `bivo` (BIVO_BINARY) on tiny rendered sequences:
// the suite renders its sequences once under a fresh temporary root (removed when the suite
// ends), each TEST works in a folder of its own named after it.
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "odometry/synth/sequence.h"
#include "tests/test_support.h"

namespace bivo::testing {

// Failure the way bad input must fail: exit 1, the message holds `part`, no internal error.
inline void expect_clear_error(const BivoRun& r, const std::string& part) {
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_TRUE(contains(r.err, part)) << r.err;
  EXPECT_FALSE(contains(r.err, "internal error")) << r.err;
}

// One rendering of the textured "structure_texture_near" scene.
struct TinySequence {
  std::string folder = "shared";  // under the suite's root ("" = the root itself)
  int frames = 4;
  std::uint64_t seed = 3;
  int supersampling = 1;  // every test is its own process: keep the rendering cheap
};

class CliSuite : public ::testing::Test {
 protected:
  // Call from the derived suite's SetUpTestSuite; `name` prefixes the temporary root.
  static void render_suite(const std::string& name, const std::vector<TinySequence>& specs = {TinySequence{}}) {
    root_ = std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(root_);
    sequences_.clear();
    for (const TinySequence& s : specs) {
      odometry::synth::SynthOptions o;
      o.category = odometry::synth::parse_category("structure_texture_near");
      o.frames = s.frames;
      o.seed = s.seed;
      o.render.supersampling = s.supersampling;
      const std::filesystem::path dir = root_ / s.folder;
      std::filesystem::create_directories(dir);
      sequences_.push_back(odometry::synth::render_sequence(o, dir.string()));
    }
    sequence_ = sequences_.front();
  }
  static void TearDownTestSuite() {
    std::filesystem::remove_all(root_);
    sequences_.clear();
  }
  void SetUp() override {
    dir_ = root_ / ::testing::UnitTest::GetInstance()->current_test_info()->name();
    std::filesystem::create_directories(dir_);
  }

  static std::string q(const std::filesystem::path& p) { return "'" + p.string() + "'"; }
  BivoRun bivo(const std::string& args) const { return run_bivo_in(args, dir_.string()); }

  static inline std::filesystem::path root_;
  static inline std::vector<std::string> sequences_;
  static inline std::string sequence_;  // the first of sequences_
  std::filesystem::path dir_;
};

}  // namespace bivo::testing
