// The study of test_study_shards.cpp on a real Slurm: a single-node cluster on localhost
// brought up by tests/slurm_local_cluster.sh (slurmctld, slurmd, munge from Debian; no
// cgroups; state in a temporary folder), the sbatch scripts of `bivo plan --slurm`
// submitted (a job array of 3 shards, throttled to 2, and the merge job that depends on it),
// waited for with a bounded timeout, and the merged tables compared with one process.
// When the daemons cannot start here the test is SKIPPED and says why.
#include <chrono>
#include <regex>
#include <thread>

#include "study_test_support.h"

namespace fs = std::filesystem;
using namespace bivo::testing;

namespace {

constexpr int kTimeoutSeconds = 240;

// Starts the cluster; stops it (and removes everything) when it goes out of scope.
class LocalSlurm {
 public:
  explicit LocalSlurm(const fs::path& dir) : dir_(dir) {
    fs::create_directories(dir_);
    const Shell r = shell("bash " + q(script()) + " start " + q(dir_), dir_.parent_path());
    status_ = r.status;
    message_ = r.err + r.out;
  }
  ~LocalSlurm() { shell("bash " + q(script()) + " stop " + q(dir_), dir_.parent_path()); }
  int status() const { return status_; }
  const std::string& message() const { return message_; }
  std::string env() const { return "SLURM_CONF=" + q(dir_ / "slurm.conf") + " "; }
  std::string logs() const {
    return slurp(dir_ / "slurmctld.log").substr(0, 4000) + "\n" + slurp(dir_ / "slurmd.log").substr(0, 4000);
  }

 private:
  static fs::path script() { return fs::path(BIVO_TESTS_DIR) / "slurm_local_cluster.sh"; }
  fs::path dir_;
  int status_ = -1;
  std::string message_;
};

TEST(StudySlurm, JobArrayAndDependentMergeGiveTheTablesOfOneProcess) {
  const TempDir temp("bivo_study_slurm");
  const fs::path& root = temp.path;
  LocalSlurm slurm(root / "cluster");
  if (slurm.status() == 77) GTEST_SKIP() << "no Slurm cluster here: " << slurm.message();
  ASSERT_EQ(slurm.status(), 0) << slurm.message();

  const std::vector<std::string> sequences = render_test_sequences(root / "sequences");
  const Shell one = shell(bivo_cli() + " report " + study_flags(sequences, root / "one"), root);
  ASSERT_EQ(one.status, 0) << one.err;

  const Shell plan = shell(bivo_cli() + " plan report " + study_flags(sequences, root / "merged") + " --study " +
                               q(root / "study.json") + " --slurm --shards 3 --throttle 2 --job-name bivotest",
                           root);
  ASSERT_EQ(plan.status, 0) << plan.err;
  const Shell submit = shell(slurm.env() + "bash " + q(root / "study.submit.sh"), root);
  ASSERT_EQ(submit.status, 0) << submit.err << submit.out;
  std::smatch ids;
  const std::regex pattern("array job ([0-9]+) .*merge job ([0-9]+)");
  ASSERT_TRUE(std::regex_search(submit.out, ids, pattern)) << submit.out;
  const std::string array = ids[1], merge = ids[2];

  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(kTimeoutSeconds);
  std::string queue;
  while (true) {
    queue = shell(slurm.env() + "squeue -h -o '%i %T %r' -j " + array + "," + merge, root).out;
    if (queue.find_first_not_of(" \n") == std::string::npos) break;
    if (std::chrono::steady_clock::now() > deadline) {
      shell(slurm.env() + "scancel " + array + " " + merge, root);
      FAIL() << "the jobs did not finish within " << kTimeoutSeconds << " s; queue:\n" << queue << slurm.logs();
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
  }
  const std::string state = shell(slurm.env() + "scontrol show job " + merge, root).out;
  EXPECT_NE(state.find("JobState=COMPLETED"), std::string::npos) << state;
  int task_logs = 0;
  for (const auto& e : fs::directory_iterator(root / "study.logs")) {
    task_logs += e.path().filename().string().rfind("bivotest-" + array + "_", 0) == 0;
  }
  EXPECT_EQ(task_logs, 3) << "one log per array task";
  EXPECT_EQ(result_files(root / "study.results"), kStudyUnits);
  expect_same_report(root / "one", root / "merged");
}

}  // namespace
