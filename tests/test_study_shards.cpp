// A sharded study gives the tables of one process. One small report study (2 sequences
// rendered by `bivo synth`, 2 methods, a 3-point lambda grid, one Pareto pair per sequence:
// 14 units) run three ways — by `bivo report` in one process, as 3 shards one after the
// other (the first one SIGKILLed midway and re-run), and as 3 shards under GNU Parallel —
// and the merged tables compared; then result files that `bivo merge` must refuse
// (truncated, foreign, duplicated, missing). One TEST does it all because ctest runs every
// TEST in a process of its own and the runs are what costs: 42 units of ~0.2 s.
#include <signal.h>

#include <algorithm>
#include <chrono>
#include <thread>

#include "study_test_support.h"

namespace fs = std::filesystem;
using namespace bivo::testing;

namespace {

struct StudyDir {
  fs::path dir;
  fs::path study() const { return dir / "study.json"; }
  fs::path merged() const { return dir / "merged"; }
};

// `bivo plan report` of the test study into d/study.json (merged output d/merged); stdout.
std::string plan(const std::vector<std::string>& sequences, const StudyDir& d, const std::string& extra = "") {
  fs::create_directories(d.dir);
  const Shell r = shell(
      bivo_cli() + " plan report " + study_flags(sequences, d.merged()) + " --study " + q(d.study()) + " " + extra,
      d.dir);
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find(std::to_string(kStudyUnits) + " unit(s)"), std::string::npos) << r.err;
  return r.out;
}

Shell work(const StudyDir& d, const std::string& shard, const fs::path& results) {
  return shell(bivo_cli() + " work " + q(d.study()) + " --shard " + shard + " --results " + q(results), d.dir);
}

Shell merge(const StudyDir& d, const fs::path& results, const std::string& extra = "") {
  return shell(bivo_cli() + " merge " + q(d.study()) + " " + q(results) + " " + extra, d.dir);
}

// Runs shard `shard` and SIGKILLs it as soon as its first result file is there (it is then
// inside its second unit); returns how many result files survived.
int run_and_kill(const StudyDir& d, const std::string& shard, const fs::path& results) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    const std::string study = d.study().string(), out = results.string(), log = (d.dir / "killed.log").string();
    std::freopen(log.c_str(), "w", stderr);
    ::execl(BIVO_BINARY, BIVO_BINARY, "work", study.c_str(), "--shard", shard.c_str(), "--results", out.c_str(),
            static_cast<char*>(nullptr));
    std::_Exit(127);
  }
  EXPECT_GE(pid, 0);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (result_files(results) == 0 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  ::kill(pid, SIGKILL);
  int status = 0;
  ::waitpid(pid, &status, 0);
  EXPECT_TRUE(WIFSIGNALED(status)) << "the shard ended before it was killed: " << slurp(d.dir / "killed.log");
  return result_files(results);
}

// The file names of the result files under `dir`, sorted.
std::vector<fs::path> result_paths(const fs::path& dir) {
  std::vector<fs::path> files;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (e.path().extension() == ".json") files.push_back(e.path());
  }
  std::sort(files.begin(), files.end(),
            [](const fs::path& a, const fs::path& b) { return a.filename() < b.filename(); });
  return files;
}

// Copies of a complete results folder with one fault each: `bivo merge` refuses them.
void expect_bad_results_refused(const StudyDir& d, const fs::path& results) {
  const std::vector<fs::path> files = result_paths(results);
  ASSERT_EQ(int(files.size()), kStudyUnits);
  auto copy_results = [&](const std::string& name) {
    const fs::path c = d.dir / name;
    fs::copy(results, c, fs::copy_options::recursive);
    return c;
  };
  auto copy_of = [&](const fs::path& c, const fs::path& file) { return c / fs::relative(file, results); };

  // Truncated (as by a copy that stopped): refused, naming the file.
  const fs::path truncated = copy_results("truncated");
  const fs::path cut = copy_of(truncated, files[3]);
  const std::string text = slurp(cut);
  std::ofstream(cut, std::ios::binary | std::ios::trunc) << text.substr(0, text.size() / 2);
  Shell r = merge(d, truncated);
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find(cut.string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("truncated"), std::string::npos) << r.err;

  // Foreign: a result of another study (other hash) in the folder: refused, naming it ...
  const fs::path foreign = copy_results("foreign");
  nlohmann::json j = nlohmann::json::parse(slurp(files[0]));
  j["study_hash"] = "0123456789abcdef";
  const fs::path stranger = foreign / "other" / "u00000_stranger.json";
  fs::create_directories(stranger.parent_path());
  std::ofstream(stranger) << j.dump();
  r = merge(d, foreign);
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find(stranger.string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("another study"), std::string::npos) << r.err;
  // ... and `bivo work` does not overwrite it.
  const fs::path in_the_way = copy_of(foreign, files[0]);
  fs::copy_file(stranger, in_the_way, fs::copy_options::overwrite_existing);
  fs::remove_all(foreign / "other");
  r = work(d, "0/1", in_the_way.parent_path());
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("another study"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(in_the_way), j.dump());

  // Duplicated: the same unit twice (two hosts ran one shard), both paths listed.
  const fs::path dup = copy_results("duplicated");
  fs::create_directories(dup / "host2");
  fs::copy_file(files[5], dup / "host2" / files[5].filename());
  r = merge(d, dup);
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("1 unit(s) with more than one result file"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find((dup / "host2" / files[5].filename()).string()), std::string::npos) << r.err;

  // Missing: unit 0 (the table cell single x first sequence) fails the merge, named ...
  const fs::path missing = copy_results("missing");
  const fs::path first = copy_of(missing, files[0]);
  ASSERT_EQ(first.filename().string().rfind("u00000_", 0), 0u) << first;
  fs::remove(first);
  r = merge(d, missing);
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("1 unit(s) missing"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("table/0-single/0-"), std::string::npos) << r.err;
  // ... unless --partial: its cell is "—", the other sequence's single cell is there.
  r = merge(d, missing, "--partial --output " + q(d.dir / "partial"));
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string rpe = slurp(d.dir / "partial/tables/rpe_trans.md");
  const auto row = rpe.find("| single |");
  ASSERT_NE(row, std::string::npos) << rpe;
  const std::string single_row = rpe.substr(row, rpe.find('\n', row) - row);
  EXPECT_NE(single_row.find("| — |"), std::string::npos) << rpe;
  EXPECT_NE(single_row.find("| 0."), std::string::npos) << rpe;
  EXPECT_NE(slurp(d.dir / "partial/tables/tables.md").find("missing from the results"), std::string::npos);
}

TEST(StudyShards, OneProcessShardsAndGnuParallelGiveTheSameTables) {
  const TempDir temp("bivo_study_shards");
  const fs::path& root = temp.path;
  const std::vector<std::string> sequences = render_test_sequences(root / "sequences");

  // 1. One process.
  const Shell one = shell(bivo_cli() + " report " + study_flags(sequences, root / "one"), root);
  ASSERT_EQ(one.status, 0) << one.err;
  ASSERT_NE(one.out.find("report: "), std::string::npos) << one.out;

  // 2. Three shards in sequence, each into a folder of its own (merge reads sub-folders);
  // shard 0 is killed after its first unit and re-run.
  const StudyDir seq{root / "sequence"};
  plan(sequences, seq);
  const fs::path results = seq.dir / "results";
  const int survived = run_and_kill(seq, "0/3", results / "shard0");
  ASSERT_GE(survived, 1);
  const Shell incomplete = merge(seq, results);
  EXPECT_EQ(incomplete.status, 1);
  EXPECT_NE(incomplete.err.find(std::to_string(kStudyUnits - survived) + " unit(s) missing"), std::string::npos)
      << incomplete.err;
  EXPECT_FALSE(fs::exists(seq.merged() / "report.md")) << "an incomplete merge wrote the report";
  for (int i = 0; i < 3; ++i) {
    const Shell r = work(seq, std::to_string(i) + "/3", results / ("shard" + std::to_string(i)));
    ASSERT_EQ(r.status, 0) << r.err;
    if (i == 0) {
      EXPECT_NE(r.err.find(std::to_string(survived) + " already done"), std::string::npos) << r.err;
    }
  }
  // Disjoint and complete: every unit once over the three folders.
  std::set<std::string> seen;
  for (const auto& file : result_paths(results)) {
    EXPECT_TRUE(seen.insert(file.filename().string()).second) << "unit in two shards: " << file;
  }
  EXPECT_EQ(int(seen.size()), kStudyUnits);
  const Shell m = merge(seq, results);
  ASSERT_EQ(m.status, 0) << m.err;
  EXPECT_NE(m.err.find("complete: 14 unit(s)"), std::string::npos) << m.err;
  // stdout is the one-process command's: the tables, then the report's path.
  EXPECT_EQ(accuracy_markdown(m.out), accuracy_markdown(one.out));
  expect_same_report(root / "one", seq.merged());

  // 3. Three shards under GNU Parallel, then the merge, by the command line `bivo plan` prints.
  if (shell("command -v parallel", root).status != 0) {
    GTEST_SKIP() << "GNU Parallel is not installed (scripts/install-deps.sh installs it)";
  }
  const StudyDir par{root / "parallel"};
  const std::string command = plan(sequences, par, "--parallel --shards 3 --jobs 2");
  EXPECT_NE(command.find("parallel "), std::string::npos) << command;
  EXPECT_NE(command.find("--shard {}/3"), std::string::npos) << command;
  EXPECT_NE(command.find("&& "), std::string::npos) << "no merge after the shards: " << command;
  const Shell p = shell(command, par.dir);
  ASSERT_EQ(p.status, 0) << command << "\n" << p.err;
  EXPECT_EQ(result_files(par.dir / "study.results"), kStudyUnits);
  expect_same_report(root / "one", par.merged());

  // 4. What merge refuses, on copies of the sequential shards' results.
  expect_bad_results_refused(seq, results);
}

TEST(StudyPlan, SlurmScriptIsAJobArrayWithADependentMerge) {
  const TempDir temp("bivo_study_plan");
  const fs::path& root = temp.path;
  // A table study reads no data when planned: its sequences need not exist.
  const std::string flags = " --sequences /data/a /data/b --methods single weighted --output " + q(root / "out") +
                            " --slurm --shards 3 --throttle 2 --time 1:00:00";
  Shell plan = shell(bivo_cli() + " plan table" + flags + " --cpus-per-task 3 --study " + q(root / "study.json"), root);
  ASSERT_EQ(plan.status, 0) << plan.err;
  EXPECT_NE(plan.out.find("bash "), std::string::npos) << plan.out;
  const std::string array = slurp(root / "study.sbatch"), submit = slurp(root / "study.submit.sh");
  EXPECT_NE(array.find("#SBATCH --array=0-2%2\n"), std::string::npos) << array;
  EXPECT_NE(array.find("#SBATCH --cpus-per-task=3\n"), std::string::npos) << array;
  EXPECT_NE(array.find("#SBATCH --time=1:00:00\n"), std::string::npos) << array;
  EXPECT_NE(array.find("--shard \"${SLURM_ARRAY_TASK_ID}/3\""), std::string::npos) << array;
  EXPECT_NE(submit.find("--dependency=afterok:${array}"), std::string::npos) << submit;
  EXPECT_NE(submit.find(" merge "), std::string::npos) << submit;
  // A command with --threads: its value is the CPUs of a task unless --cpus-per-task is given.
  if (shell(bivo_cli() + " plan table --help", root).out.find("  --threads ") != std::string::npos) {
    plan = shell(bivo_cli() + " plan table" + flags + " --threads 2 --study " + q(root / "t.json"), root);
    ASSERT_EQ(plan.status, 0) << plan.err;
    EXPECT_NE(slurp(root / "t.sbatch").find("#SBATCH --cpus-per-task=2\n"), std::string::npos)
        << slurp(root / "t.sbatch");
  }
  // Both parse as bash.
  EXPECT_EQ(shell("bash -n " + q(root / "study.sbatch") + " && bash -n " + q(root / "study.submit.sh"), root).status,
            0);
}

}  // namespace
