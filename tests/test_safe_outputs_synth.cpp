// `bivo synth` and its output folder, through the built binary, one test per reproducer: a
// folder or symlink bivo did not write is never deleted or replaced, its own input is never
// written over, and what a killed run left is removed by the next run on the same output
// (only what carries bivo's record of a dead process). Tiny renderings: 2 frames, no
// supersampling, one thread.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <climits>
#include <filesystem>
#include <fstream>
#include <thread>

#include <gtest/gtest.h>

#include "tests/support/cli_suite.h"

extern char** environ;

namespace fs = std::filesystem;
using bivo::testing::BivoRun;
using bivo::testing::contains;
using bivo::testing::expect_clear_error;
using bivo::testing::slurp;

namespace {

const char kTiny[] = " --category structure_texture_near --frames 2 --supersampling 1 --threads 1";

class SafeSynth : public ::testing::Test {
 protected:
  SafeSynth() : tmp_("bivo_safe_synth_" + name()), dir_(tmp_.path / "D"), scratch_(tmp_.path / "scratch") {
    fs::create_directories(dir_);
    fs::create_directories(scratch_);
  }
  static std::string name() { return ::testing::UnitTest::GetInstance()->current_test_info()->name(); }
  static std::string q(const fs::path& p) { return "'" + p.string() + "'"; }
  BivoRun bivo(const std::string& args) const { return bivo::testing::run_bivo_in(args, scratch_.string()); }
  BivoRun synth(const std::string& folder_name, const std::string& more = "") const {
    return bivo("synth" + std::string(kTiny) + " --output " + q(dir_) + " --name " + folder_name + " " + more);
  }
  // The names in D: nothing left beside what the test expects.
  std::vector<std::string> entries() const {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir_)) out.push_back(e.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
  }

  bivo::testing::TempDir tmp_;
  fs::path dir_, scratch_;
};

}  // namespace

// synth deleted an existing D/N holding the user's own files (with or without --force).
TEST_F(SafeSynth, ExistingFolderOfTheUserIsKept) {
  fs::create_directories(dir_ / "n_freiburg3");
  std::ofstream(dir_ / "n_freiburg3" / "notes.txt") << "mine\n";
  for (const char* force : {"", "--force"}) {
    expect_clear_error(synth("n_freiburg3", force), "refusing to replace '" + (dir_ / "n_freiburg3").string() + "'");
  }
  EXPECT_EQ(slurp(dir_ / "n_freiburg3" / "notes.txt"), "mine\n");
  EXPECT_EQ(entries(), std::vector<std::string>{"n_freiburg3"});
}

// synth removed a D/N.tmp-render folder of the user's (its old temporary name).
TEST_F(SafeSynth, FolderNamedLikeTheOldTemporaryIsKept) {
  fs::create_directories(dir_ / "n_freiburg3.tmp-render");
  std::ofstream(dir_ / "n_freiburg3.tmp-render" / "notes.txt") << "mine\n";
  const BivoRun r = synth("n_freiburg3");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(slurp(dir_ / "n_freiburg3.tmp-render" / "notes.txt"), "mine\n");
  EXPECT_EQ(entries(), (std::vector<std::string>{"n_freiburg3", "n_freiburg3.tmp-render"}));
}

// synth replaced a D/N that is a symlink to a folder elsewhere (even one bivo rendered).
TEST_F(SafeSynth, SymlinkTargetIsNeverReplaced) {
  const fs::path elsewhere = tmp_.path / "elsewhere";
  ASSERT_EQ(bivo("synth" + std::string(kTiny) + " --output " + q(elsewhere) + " --name e_freiburg3").status, 0);
  const std::string before = slurp(elsewhere / "e_freiburg3" / "groundtruth.txt");
  fs::create_directory_symlink(elsewhere / "e_freiburg3", dir_ / "n_freiburg3");
  for (const char* force : {"", "--force"}) {
    expect_clear_error(synth("n_freiburg3", std::string(force) + " --seed 9"), "symbolic link");
  }
  EXPECT_TRUE(fs::is_symlink(dir_ / "n_freiburg3"));
  EXPECT_EQ(slurp(elsewhere / "e_freiburg3" / "groundtruth.txt"), before);
  EXPECT_EQ(entries(), std::vector<std::string>{"n_freiburg3"});
}

// With --trajectory D/N/groundtruth.txt synth overwrote its own input; a hard link to it
// elsewhere names the same file.
TEST_F(SafeSynth, TrajectoryInsideTheTargetIsRefused) {
  ASSERT_EQ(synth("n_freiburg3").status, 0);
  const fs::path gt = dir_ / "n_freiburg3" / "groundtruth.txt";
  const std::string before = slurp(gt);
  fs::create_hard_link(gt, tmp_.path / "linked.txt");
  for (const fs::path& trajectory : {gt, tmp_.path / "linked.txt"}) {
    expect_clear_error(synth("n_freiburg3", "--force --trajectory " + q(trajectory)),
                       "--trajectory '" + trajectory.string() + "' is inside the output folder");
  }
  EXPECT_EQ(slurp(gt), before);
  EXPECT_EQ(entries(), std::vector<std::string>{"n_freiburg3"});
}

// A folder bivo rendered is refused without --force and replaced with it (other seed, other
// ground truth); nothing is left beside it.
TEST_F(SafeSynth, OwnFolderIsReplacedOnlyWithForce) {
  ASSERT_EQ(synth("n_freiburg3", "--seed 1").status, 0);
  const fs::path gt = dir_ / "n_freiburg3" / "groundtruth.txt";
  const std::string first = slurp(gt);
  expect_clear_error(synth("n_freiburg3", "--seed 2"), "--force replaces it");
  EXPECT_EQ(slurp(gt), first);
  const BivoRun r = synth("n_freiburg3", "--seed 2 --force");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(slurp(gt), first);
  EXPECT_TRUE(fs::is_regular_file(dir_ / "n_freiburg3" / ".bivo-output"));
  EXPECT_EQ(entries(), std::vector<std::string>{"n_freiburg3"});
}

// A SIGKILLed synth left its partial temporary folder; the next run on the same output
// removes it (its owner record names a dead process of this host), and nothing else.
TEST_F(SafeSynth, KilledRunsTemporaryIsRemovedByTheNextRun) {
  fs::create_directories(dir_ / "n_freiburg3.tmp-bivo.1.2.elsewhere");  // no owner record: kept
  const std::string bin = BIVO_BINARY, out = dir_.string();
  std::vector<std::string> args{bin,         "synth",      "--category",      "structure_texture_near",
                                "--frames",  "400",        "--supersampling", "1",
                                "--threads", "1",          "--output",        out,
                                "--name",    "n_freiburg3"};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  pid_t pid = 0;
  ASSERT_EQ(posix_spawn(&pid, bin.c_str(), &actions, nullptr, argv.data(), environ), 0);
  posix_spawn_file_actions_destroy(&actions);
  // Killed once it has written frames into its temporary folder.
  fs::path partial;
  for (int k = 0; k < 1000 && partial.empty(); ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    for (const auto& e : fs::directory_iterator(dir_)) {
      const std::string n = e.path().filename().string();
      if (n.rfind("n_freiburg3.tmp-bivo." + std::to_string(pid) + ".", 0) == 0 && fs::exists(e.path() / "rgb") &&
          !fs::is_empty(e.path() / "rgb")) {
        partial = e.path();
      }
    }
  }
  ::kill(pid, SIGKILL);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_FALSE(partial.empty()) << "the run never wrote a frame";
  ASSERT_TRUE(fs::exists(partial));
  ASSERT_FALSE(fs::exists(dir_ / "n_freiburg3"));
  const BivoRun r = synth("n_freiburg3");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_FALSE(fs::exists(partial));
  EXPECT_EQ(entries(), (std::vector<std::string>{"n_freiburg3", "n_freiburg3.tmp-bivo.1.2.elsewhere"}));
}

// A killed `bivo run` left "<output>.tmp..." behind: the next run on that output removes the
// temporaries of dead processes of this host, and keeps a user's look-alike and a live one's.
TEST_F(SafeSynth, KilledRunsTemporaryFileIsRemovedByTheNextRun) {
  ASSERT_EQ(synth("n_freiburg3").status, 0);
  char host[HOST_NAME_MAX + 1] = {};
  ASSERT_EQ(::gethostname(host, HOST_NAME_MAX), 0);
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ASSERT_GT(child, 0);
  ::waitpid(child, nullptr, 0);  // a pid that has surely ended
  const fs::path out = tmp_.path / "t.txt";
  const std::string dead = "t.txt.tmp-bivo." + std::to_string(child) + ".ab." + host;
  const std::string alive = "t.txt.tmp-bivo." + std::to_string(::getpid()) + ".ab." + host;
  for (const std::string& n : {dead, alive, std::string("t.txt.tmp-user"), std::string("t.txt.tmp-bivo.notes")}) {
    std::ofstream(tmp_.path / n) << "partial";
  }
  const BivoRun r = bivo("run " + q(dir_ / "n_freiburg3") + " --method single --levels 2 --output " + q(out));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_FALSE(fs::exists(tmp_.path / dead));
  for (const std::string& n : {alive, std::string("t.txt.tmp-user"), std::string("t.txt.tmp-bivo.notes")}) {
    EXPECT_EQ(slurp(tmp_.path / n), "partial") << n;
  }
}
