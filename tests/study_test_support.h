#pragma once
// Shared by the sharded-study tests (test_study_shards.cpp, test_study_slurm.cpp): the built
// `bivo` (BIVO_BINARY) run through a shell, two tiny rendered sequences, the study they run
// (a report: 2 methods x 2 sequences, a 3-point lambda grid, one Pareto pair per sequence:
// 14 units), and the comparison of two output folders with the timing columns taken out.
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "test_support.h"

namespace bivo::testing {

namespace fs = std::filesystem;

inline std::string q(const fs::path& p) { return "'" + p.string() + "'"; }

struct Shell {
  int status = -1;
  std::string out, err;
};

// Runs `command` with sh; stdout/stderr go through files in `dir`.
inline Shell shell(const std::string& command, const fs::path& dir) {
  const fs::path out = dir / "shell.out", err = dir / "shell.err";
  const std::string cmd = "(" + command + ") >" + q(out) + " 2>" + q(err);
  const int raw = std::system(cmd.c_str());
  Shell r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

inline std::string bivo_cli() { return q(BIVO_BINARY); }

// Two 5-frame sequences (textured plane, and zig-zag panels on a floor) rendered by
// `bivo synth`: 2 frames per second, so that 5 frames hold two 1-s RPE windows, and slow
// hand-held motion, so that the pairs stay trackable at the coarse level the study uses.
inline std::vector<std::string> render_test_sequences(const fs::path& dir) {
  std::vector<std::string> out;
  for (const char* category : {"structure_texture_near", "nostructure_texture_near"}) {
    const Shell r = shell(bivo_cli() + " synth --category " + category +
                              " --frames 5 --fps 2 --seed 5 --speed 0.03 --angular-speed 2 --supersampling 1"
                              " --threads 1 --output " +
                              q(dir),
                          dir.parent_path());
    EXPECT_EQ(r.status, 0) << r.err;
    out.push_back((dir / (std::string("rgbd_dataset_freiburg3_synth_") + category)).string());
  }
  return out;
}

// The flags of the test study after `bivo report` / `bivo plan report`.
inline std::string study_flags(const std::vector<std::string>& sequences, const fs::path& output) {
  std::string s = "--sequences";
  for (const auto& seq : sequences) s += " " + q(seq);
  return s +
         " --methods single weighted --lambda-points 3 --lambda-min 100 --lambda-max 1e5 --eps-points 0"
         " --max-frames 5 --sweep-frames 5 --levels 4 --finest-level 3 --pareto-level 3 --pareto-points 4"
         " --no-plots --output " +
         q(output);
}
constexpr int kStudyUnits = 4 + 2 * 4 + 2;

// Timing columns and keys: they differ from run to run; everything else must not.
inline const std::set<std::string>& timing_names() {
  static const std::set<std::string> names{"ms", "median_ms", "mean_ms", "seconds", "ms_per_pair_by_phase"};
  return names;
}

inline std::string without_timing_columns(const std::string& csv) {
  std::istringstream in(csv);
  std::string line, out;
  std::vector<bool> keep;
  while (std::getline(in, line)) {
    std::vector<std::string> fields;
    std::stringstream ls(line);
    std::string f;
    while (std::getline(ls, f, ',')) fields.push_back(f);
    if (keep.empty()) {
      for (const auto& name : fields) keep.push_back(!timing_names().count(name));
    }
    for (size_t k = 0; k < fields.size(); ++k) {
      if (k >= keep.size() || keep[k]) out += fields[k] + ",";
    }
    out += "\n";
  }
  return out;
}

inline void erase_timing(nlohmann::json& j) {
  if (j.is_object()) {
    for (const auto& name : timing_names()) j.erase(name);
    for (auto& [key, value] : j.items()) erase_timing(value);
  } else if (j.is_array()) {
    for (auto& value : j) erase_timing(value);
  }
}

inline std::string without_timing_keys(const std::string& text) {
  nlohmann::json j = nlohmann::json::parse(text);
  erase_timing(j);
  return j.dump(1);
}

// The Markdown tables up to the runtime ones.
inline std::string accuracy_markdown(const std::string& md) { return md.substr(0, md.find("Time per frame pair")); }

// Every table, JSON and trajectory of two report folders, equal up to timing. Also checks
// that the tables are not empty, so two failed runs do not compare equal.
inline void expect_same_report(const fs::path& want, const fs::path& got) {
  ASSERT_TRUE(fs::exists(want / "report.md")) << want;
  ASSERT_TRUE(fs::exists(got / "report.md")) << got;
  const std::string rpe = slurp(want / "tables/rpe_trans.csv");
  EXPECT_NE(rpe.find("single,0."), std::string::npos) << "no RPE of single in " << want << ":\n" << rpe;
  EXPECT_NE(slurp(want / "sweep/sweep.csv").find("lambda"), std::string::npos);
  for (const char* exact :
       {"tables/rpe_trans.md", "tables/rpe_trans.csv", "tables/rpe_rot.csv", "tables/ate.csv", "config.json"}) {
    EXPECT_EQ(slurp(want / exact), slurp(got / exact)) << exact;
  }
  EXPECT_EQ(accuracy_markdown(slurp(want / "tables/tables.md")), accuracy_markdown(slurp(got / "tables/tables.md")));
  for (const char* csv : {"tables/pairs.csv", "sweep/sweep.csv"}) {
    EXPECT_EQ(without_timing_columns(slurp(want / csv)), without_timing_columns(slurp(got / csv))) << csv;
  }
  std::set<std::string> jsons{"tables/results.json", "sweep/sweep.json"};
  for (const auto& e : fs::directory_iterator(want / "pareto")) jsons.insert("pareto/" + e.path().filename().string());
  EXPECT_EQ(jsons.size(), 4u) << "expected one Pareto JSON per sequence";
  for (const auto& name : jsons) {
    ASSERT_TRUE(fs::exists(got / name)) << name;
    EXPECT_EQ(without_timing_keys(slurp(want / name)), without_timing_keys(slurp(got / name))) << name;
  }
  int trajectories = 0;
  for (const auto& e : fs::directory_iterator(want / "trajectories")) {
    ++trajectories;
    EXPECT_EQ(slurp(e.path()), slurp(got / "trajectories" / e.path().filename())) << e.path().filename();
  }
  EXPECT_EQ(trajectories, 4);
}

// The result files of a results folder.
inline int result_files(const fs::path& dir) {
  int n = 0;
  if (!fs::exists(dir)) return 0;
  for (const auto& e : fs::recursive_directory_iterator(dir)) n += e.path().extension() == ".json";
  return n;
}

}  // namespace bivo::testing
