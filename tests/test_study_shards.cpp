// A sharded study gives the tables of one process: a small report study (2 rendered
// sequences, 2 methods, a 3-point lambda grid, 14 units) run by `bivo report` in one
// process, as 3 shards one after the other, and as 3 shards under GNU Parallel; then the
// faults: a shard killed (SIGKILL) midway and re-run, truncated, foreign and duplicated
// result files, missing units with and without --partial.
#include <signal.h>

#include <algorithm>
#include <chrono>
#include <thread>

#include "study_test_support.h"

namespace fs = std::filesystem;
using namespace bivo::testing;

namespace {

class StudyShards : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    root_ = fs::temp_directory_path() / ("bivo_study_shards_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_);
    sequences_ = render_test_sequences(root_ / "sequences");
    const Shell r = shell(bivo_cli() + " report " + study_flags(sequences_, root_ / "one"), root_);
    ASSERT_EQ(r.status, 0) << r.err;
    ASSERT_NE(r.out.find("report: "), std::string::npos) << r.out;
  }
  static void TearDownTestSuite() { fs::remove_all(root_); }
  void SetUp() override {
    ASSERT_TRUE(fs::exists(root_ / "one/report.md")) << "the one-process run failed (see SetUpTestSuite)";
    dir_ = root_ / ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::create_directories(dir_);
  }
  // Plans the test study into dir_/study.json (merged output dir_/merged); returns stdout.
  std::string plan(const std::string& extra = "") {
    const Shell r = shell(bivo_cli() + " plan report " + study_flags(sequences_, dir_ / "merged") + " --study " +
                              q(dir_ / "study.json") + " " + extra,
                          dir_);
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find(std::to_string(kStudyUnits) + " unit(s)"), std::string::npos) << r.err;
    return r.out;
  }
  Shell work(const std::string& shard) {
    return shell(bivo_cli() + " work " + q(dir_ / "study.json") + " --shard " + shard, dir_);
  }
  Shell merge(const fs::path& results, const std::string& extra = "") {
    return shell(bivo_cli() + " merge " + q(dir_ / "study.json") + " " + q(results) + " " + extra, dir_);
  }
  fs::path results() const { return dir_ / "study.results"; }

  static fs::path root_;
  static std::vector<std::string> sequences_;
  fs::path dir_;
};
fs::path StudyShards::root_;
std::vector<std::string> StudyShards::sequences_;

TEST_F(StudyShards, ThreeShardsInSequenceGiveTheTablesOfOneProcess) {
  plan();
  for (int i = 0; i < 3; ++i) {
    const Shell r = work(std::to_string(i) + "/3");
    ASSERT_EQ(r.status, 0) << r.err;
  }
  EXPECT_EQ(result_files(results()), kStudyUnits);
  const Shell m = merge(results());
  ASSERT_EQ(m.status, 0) << m.err;
  EXPECT_NE(m.err.find("complete: 14 unit(s)"), std::string::npos) << m.err;
  // stdout is the one-process command's: the tables, then the report's path.
  EXPECT_EQ(accuracy_markdown(m.out), accuracy_markdown(slurp(root_ / "one/tables/tables.md")));
  expect_same_report(root_ / "one", dir_ / "merged");
}

TEST_F(StudyShards, ShardsAreDisjointAndCoverEveryUnit) {
  plan();
  std::set<std::string> seen;
  for (int i = 0; i < 3; ++i) {
    const fs::path before = dir_ / ("shard" + std::to_string(i));
    ASSERT_EQ(shell(bivo_cli() + " work " + q(dir_ / "study.json") + " --shard " + std::to_string(i) + "/3 --results " +
                        q(before), dir_).status, 0);
    for (const auto& e : fs::directory_iterator(before)) {
      EXPECT_TRUE(seen.insert(e.path().filename().string()).second) << "unit in two shards: " << e.path();
    }
  }
  EXPECT_EQ(int(seen.size()), kStudyUnits);
}

TEST_F(StudyShards, ThreeShardsUnderGnuParallelGiveTheTablesOfOneProcess) {
  if (shell("command -v parallel", dir_).status != 0) {
    GTEST_SKIP() << "GNU Parallel is not installed (scripts/install-deps.sh installs it)";
  }
  const std::string command = plan("--parallel --shards 3 --jobs 2");
  EXPECT_NE(command.find("parallel "), std::string::npos) << command;
  EXPECT_NE(command.find("--shard {}/3"), std::string::npos) << command;
  EXPECT_NE(command.find("&& "), std::string::npos) << "no merge after the shards: " << command;
  const Shell r = shell(command, dir_);
  ASSERT_EQ(r.status, 0) << command << "\n" << r.err;
  EXPECT_EQ(result_files(results()), kStudyUnits);
  expect_same_report(root_ / "one", dir_ / "merged");
}

TEST_F(StudyShards, AShardKilledMidwayResumesAndTheMergeIsComplete) {
  plan();
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    const std::string study = (dir_ / "study.json").string(), log = (dir_ / "killed.log").string();
    std::freopen(log.c_str(), "w", stderr);
    ::execl(BIVO_BINARY, BIVO_BINARY, "work", study.c_str(), "--shard", "0/1", static_cast<char*>(nullptr));
    std::_Exit(127);
  }
  // Kill it as soon as the first unit is written: it is then inside the second one.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (result_files(results()) == 0 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ::kill(pid, SIGKILL);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the shard ended before it was killed";
  const int done = result_files(results());
  ASSERT_GE(done, 1);
  ASSERT_LT(done, kStudyUnits) << "every unit was done before the kill: nothing to resume";

  const Shell incomplete = merge(results());
  EXPECT_EQ(incomplete.status, 1);
  EXPECT_NE(incomplete.err.find(std::to_string(kStudyUnits - done) + " unit(s) missing"), std::string::npos)
      << incomplete.err;
  EXPECT_FALSE(fs::exists(dir_ / "merged/report.md"));

  const Shell resumed = work("0/1");
  ASSERT_EQ(resumed.status, 0) << resumed.err;
  EXPECT_NE(resumed.err.find(std::to_string(kStudyUnits - done) + " unit(s) run, " + std::to_string(done) +
                             " already done"),
            std::string::npos)
      << resumed.err;
  const Shell m = merge(results());
  ASSERT_EQ(m.status, 0) << m.err;
  expect_same_report(root_ / "one", dir_ / "merged");
}

TEST_F(StudyShards, TruncatedForeignAndDuplicatedResultsAreRefused) {
  plan();
  ASSERT_EQ(work("0/1").status, 0);
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(results())) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  ASSERT_EQ(int(files.size()), kStudyUnits);

  auto copy_results = [&](const std::string& name) {
    const fs::path d = dir_ / name;
    fs::copy(results(), d);
    return d;
  };
  // Truncated (as by a copy that stopped): refused, naming the file.
  const fs::path truncated = copy_results("truncated");
  const fs::path cut = truncated / files[3].filename();
  const std::string text = slurp(cut);
  std::ofstream(cut, std::ios::binary | std::ios::trunc) << text.substr(0, text.size() / 2);
  Shell r = merge(truncated);
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find(cut.string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("truncated"), std::string::npos) << r.err;

  // Foreign: a result of another study (other hash) in the folder.
  const fs::path foreign = copy_results("foreign");
  nlohmann::json j = nlohmann::json::parse(slurp(files[0]));
  j["study_hash"] = "0123456789abcdef";
  const fs::path stranger = foreign / "other" / "u00000_stranger.json";
  fs::create_directories(stranger.parent_path());
  std::ofstream(stranger) << j.dump();
  r = merge(foreign);
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find(stranger.string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("another study"), std::string::npos) << r.err;
  // ... and `bivo work` will not overwrite it.
  fs::copy_file(stranger, foreign / files[0].filename(), fs::copy_options::overwrite_existing);
  fs::remove_all(foreign / "other");
  r = shell(bivo_cli() + " work " + q(dir_ / "study.json") + " --results " + q(foreign), dir_);
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("another study"), std::string::npos) << r.err;

  // Duplicated: the same unit twice (two hosts ran one shard).
  const fs::path dup = copy_results("duplicated");
  fs::create_directories(dup / "host2");
  fs::copy_file(files[5], dup / "host2" / files[5].filename());
  r = merge(dup);
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("1 unit(s) with more than one result file"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find((dup / "host2" / files[5].filename()).string()), std::string::npos) << r.err;
}

TEST_F(StudyShards, MissingUnitsFailTheMergeUnlessPartial) {
  plan();
  ASSERT_EQ(work("0/1").status, 0);
  // Unit 0 is the table cell single x first sequence.
  fs::path first;
  for (const auto& e : fs::directory_iterator(results())) {
    if (e.path().filename().string().rfind("u00000_", 0) == 0) first = e.path();
  }
  ASSERT_FALSE(first.empty());
  fs::remove(first);
  Shell r = merge(results());
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("1 unit(s) missing"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("table/0-single/0-"), std::string::npos) << r.err;

  r = merge(results(), "--partial");
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string rpe = slurp(dir_ / "merged/tables/rpe_trans.md");
  // The missing cell is "—"; the other sequence's single cell is there.
  const std::string single_row = rpe.substr(rpe.find("| single |"), rpe.find('\n', rpe.find("| single |")) - rpe.find("| single |"));
  EXPECT_NE(single_row.find("| — |"), std::string::npos) << rpe;
  EXPECT_NE(slurp(dir_ / "merged/tables/tables.md").find("missing from the results"), std::string::npos);
}

TEST_F(StudyShards, SlurmScriptIsAJobArrayWithADependentMerge) {
  const std::string out = plan("--slurm --shards 3 --throttle 2 --cpus-per-task 2 --time 1:00:00");
  EXPECT_NE(out.find("bash "), std::string::npos) << out;
  const std::string array = slurp(dir_ / "study.sbatch"), submit = slurp(dir_ / "study.submit.sh");
  EXPECT_NE(array.find("#SBATCH --array=0-2%2\n"), std::string::npos) << array;
  EXPECT_NE(array.find("#SBATCH --cpus-per-task=2\n"), std::string::npos) << array;
  EXPECT_NE(array.find("#SBATCH --time=1:00:00\n"), std::string::npos) << array;
  EXPECT_NE(array.find("--shard \"${SLURM_ARRAY_TASK_ID}/3\""), std::string::npos) << array;
  EXPECT_NE(submit.find("--dependency=afterok:${array}"), std::string::npos) << submit;
  EXPECT_NE(submit.find(" merge "), std::string::npos) << submit;
  // Both parse as bash.
  EXPECT_EQ(shell("bash -n " + q(dir_ / "study.sbatch") + " && bash -n " + q(dir_ / "study.submit.sh"), dir_).status, 0);
}

}  // namespace
