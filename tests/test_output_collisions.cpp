// Outputs that land on a command's inputs, through the built `bivo`, one test per kind of
// collision over every subcommand that writes: each is refused before any work (no unit run,
// no output folder made) with exit 1 and a message naming both paths, and nothing of the
// user's changes. Symlinks and hard links do not hide a collision.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>

#include <gtest/gtest.h>

#include "tests/support/cli_suite.h"

namespace fs = std::filesystem;
using bivo::testing::BivoRun;
using bivo::testing::contains;
using bivo::testing::slurp;

namespace {

class OutputCollisions : public bivo::testing::CliSuite {
 protected:
  static void SetUpTestSuite() { render_suite("bivo_output_collisions"); }

  // Every file under `dir` (relative path -> bytes): the user's data before and after.
  static std::map<std::string, std::string> tree(const fs::path& dir) {
    std::map<std::string, std::string> out;
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
      out[fs::relative(e.path(), dir).string()] = e.is_regular_file() ? slurp(e.path()) : "<folder>";
    }
    return out;
  }
  // Refused before any work: exit 1, both paths named, no unit run.
  static void expect_refused(const BivoRun& r, const std::string& name, const std::string& first,
                             const std::string& second) {
    EXPECT_EQ(r.status, 1) << name << ": " << r.err;
    EXPECT_TRUE(contains(r.err, "'" + first + "'")) << name << ": " << r.err;
    EXPECT_TRUE(contains(r.err, "'" + second + "'")) << name << ": " << r.err;
    EXPECT_FALSE(contains(r.err, "[1/")) << name << ": a unit ran first: " << r.err;
    EXPECT_FALSE(contains(r.err, "internal error")) << name << ": " << r.err;
  }
  // Every command that writes a folder (`--output`, `work`'s `--results`) with `out` as that
  // folder, on this suite's sequence; `study` is a planned table study for work and merge.
  std::vector<std::pair<std::string, std::string>> folder_commands(const fs::path& out, const fs::path& study,
                                                                   const std::string& more = "") const {
    const std::string seq = q(sequence_), o = " --output " + q(out) + more;
    return {{"table", "table --sequences " + seq + " --methods single --levels 2" + o},
            {"sweep", "sweep --sequences " + seq + " --lambda-points 2 --eps-points 0 --levels 2" + o},
            {"pareto", "pareto " + seq + " --pair 0 --points 3 --levels 2 --no-plots" + o},
            {"report", "report --sequences " + seq +
                           " --methods single --lambda-points 0 --eps-points 0 --no-pareto --levels 2 --no-plots" + o},
            {"loso", "loso --sequences " + seq + " " + seq + " --method robust --parameter trust --grid 0.3" + o},
            {"profile", "profile " + seq + " --methods single:gn --repetitions 1 --levels 2" + o},
            {"plan", "plan table --sequences " + seq + " --methods single --study " + q(dir_ / "p.json") + o},
            {"merge", "merge " + q(study) + o},
            {"work", "work " + q(study) + " --results " + q(out) + more}};
  }
  // A one-unit table study planned in this test's folder (its results beside it).
  fs::path plan_study() const {
    const fs::path study = dir_ / "planned" / "s.json";
    fs::create_directories(study.parent_path());
    const BivoRun r =
        bivo("plan table --sequences " + q(sequence_) + " --methods single --levels 2 --max-frames 2 --output " +
             q(dir_ / "merged") + " --study " + q(study));
    EXPECT_EQ(r.status, 0) << r.err;
    return study;
  }
};

}  // namespace

// `table --output SEQ` wrote its tables into the sequence folder it read.
TEST_F(OutputCollisions, OutputFolderIsASequenceFolder) {
  const fs::path study = plan_study();
  const auto before = tree(sequence_);
  for (const auto& [name, args] : folder_commands(sequence_, study)) {
    expect_refused(bivo(args), name, sequence_, sequence_);
    EXPECT_EQ(tree(sequence_), before) << name;
  }
  EXPECT_FALSE(fs::exists(dir_ / "p.json"));
}

TEST_F(OutputCollisions, OutputFolderInsideASequenceFolder) {
  const fs::path study = plan_study();
  const auto before = tree(sequence_);
  const fs::path out = fs::path(sequence_) / "rgb" / "results";
  for (const auto& [name, args] : folder_commands(out, study)) {
    const BivoRun r = bivo(args);
    expect_refused(r, name, out.string(), sequence_);
    EXPECT_TRUE(contains(r.err, "lies in")) << name << ": " << r.err;
    EXPECT_EQ(tree(sequence_), before) << name;
  }
}

// The sequence reached through a symlinked folder, or the output folder itself a symlink to it.
TEST_F(OutputCollisions, OutputFolderReachesTheSequenceThroughASymlink) {
  const fs::path study = plan_study();
  fs::create_directory_symlink(sequence_, dir_ / "alias");
  const auto before = tree(sequence_);
  for (const fs::path& out : {dir_ / "alias", dir_ / "alias" / "depth" / "out"}) {
    for (const auto& [name, args] : folder_commands(out, study)) {
      expect_refused(bivo(args), name, out.string(), sequence_);
      EXPECT_EQ(tree(sequence_), before) << name;
    }
  }
}

// `table --config out/config.json --output out` replaced its configuration after all the work.
TEST_F(OutputCollisions, ConfigFileInsideTheOutputFolder) {
  const std::string config = "{\"method\": \"single\", \"levels\": 2}\n";
  const fs::path out = dir_ / "out";
  fs::create_directories(out);
  std::ofstream(out / "config.json") << config;
  const fs::path study = plan_study();
  for (const auto& [name, args] : folder_commands(out, study, " --config " + q(out / "config.json"))) {
    if (name == "merge" || name == "work") continue;  // no --config: their study is the input (below)
    expect_refused(bivo(args), name, (out / "config.json").string(), out.string());
    EXPECT_EQ(tree(out), (std::map<std::string, std::string>{{"config.json", config}})) << name;
  }
  // A hard link to a file of the output folder is that file under another name.
  fs::create_hard_link(out / "config.json", dir_ / "linked.json");
  const BivoRun r =
      bivo("table --sequences " + q(sequence_) + " --config " + q(dir_ / "linked.json") + " --output " + q(out));
  expect_refused(r, "table", (dir_ / "linked.json").string(), (out / "config.json").string());
  EXPECT_EQ(tree(out), (std::map<std::string, std::string>{{"config.json", config}}));
}

// A study file inside the folder work writes results to (merge would read it as a result), or
// inside the folder merge writes (merge wrote study.json over it).
TEST_F(OutputCollisions, StudyFileInsideTheResultsOrOutputFolder) {
  const fs::path study = plan_study(), folder = study.parent_path();
  const std::string planned = slurp(study);
  expect_refused(bivo("work " + q(study) + " --results " + q(folder)), "work", study.string(), folder.string());
  ASSERT_EQ(bivo("work " + q(study)).status, 0);
  const auto before = tree(folder);
  expect_refused(bivo("merge " + q(study) + " --output " + q(folder)), "merge", study.string(), folder.string());
  // Merged into its own results folder, the merge's files would be taken for results next time.
  const fs::path results = folder / "s.results";
  expect_refused(bivo("merge " + q(study) + " --output " + q(results / "merged")), "merge",
                 (results / "merged").string(), results.string());
  EXPECT_EQ(tree(folder), before);
  EXPECT_EQ(slurp(study), planned);
  EXPECT_FALSE(fs::exists(dir_ / "merged"));
}

// `plan --study` on its own --config (by name or hard link), or inside a sequence folder.
TEST_F(OutputCollisions, PlanStudyFileOnAnInput) {
  const std::string config = "{\"levels\": 2}\n";
  std::ofstream(dir_ / "cfg.json") << config;
  fs::create_hard_link(dir_ / "cfg.json", dir_ / "cfg-link.json");
  const std::string plan = "plan table --sequences " + q(sequence_) + " --output " + q(dir_ / "o") + " --study ";
  expect_refused(bivo(plan + q(dir_ / "cfg.json") + " --config " + q(dir_ / "cfg.json")), "plan",
                 (dir_ / "cfg.json").string(), (dir_ / "cfg.json").string());
  const BivoRun linked = bivo(plan + q(dir_ / "cfg-link.json") + " --config " + q(dir_ / "cfg.json"));
  expect_refused(linked, "plan", (dir_ / "cfg-link.json").string(), (dir_ / "cfg.json").string());
  EXPECT_EQ(slurp(dir_ / "cfg.json"), config);
  const auto before = tree(sequence_);
  const fs::path inside = fs::path(sequence_) / "study.json";
  expect_refused(bivo(plan + q(inside) + " --slurm"), "plan", inside.string(), sequence_);
  EXPECT_EQ(tree(sequence_), before);
}

// `run`: the configuration written beside --output or by --save-config on the --config read.
TEST_F(OutputCollisions, RunConfigurationOnItsOwnConfig) {
  const std::string config = "{\"method\": \"single\", \"levels\": 2}\n";
  std::ofstream(dir_ / "t.config.json") << config;
  const std::string run = "run " + q(sequence_) + " --config " + q(dir_ / "t.config.json");
  expect_refused(bivo(run + " --output " + q(dir_ / "t.txt")), "run", (dir_ / "t.config.json").string(),
                 (dir_ / "t.config.json").string());
  expect_refused(bivo(run + " --save-config " + q(dir_ / "t.config.json")), "run", (dir_ / "t.config.json").string(),
                 (dir_ / "t.config.json").string());
  EXPECT_EQ(slurp(dir_ / "t.config.json"), config);
  EXPECT_FALSE(fs::exists(dir_ / "t.txt"));
}
