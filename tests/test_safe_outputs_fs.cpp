// Filesystem faults and hostile files through the built `bivo`, one test per reproducer:
// each ends with exit 1 and a message naming the path or value (never "internal error"),
// nothing of the user's changed and nothing partial left. Tests run as root in CI, which
// ignores permission bits: a folder the system refuses is one under /proc, on a read-only
// tmpfs mounted here (skipped, saying why, where mounting is not allowed), or a file size
// limit (RLIMIT_FSIZE) standing in for a full disk.
#include <sys/mount.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "experiments/study/study.h"
#include "experiments/study/study_work.h"
#include "tests/support/cli_suite.h"

namespace fs = std::filesystem;
using bivo::testing::BivoRun;
using bivo::testing::contains;
using bivo::testing::expect_clear_error;
using bivo::testing::slurp;

namespace {

class SafeFs : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    shared_ = std::make_unique<bivo::testing::TempDir>("bivo_safe_fs");
    const BivoRun r = bivo::testing::run_bivo_in(
        "synth --category structure_texture_near --frames 2 --supersampling 1 --threads 1 --output " +
            q(shared_->path) + " --name s_freiburg3",
        shared_->path.string());
    ASSERT_EQ(r.status, 0) << r.err;
    sequence_ = (shared_->path / "s_freiburg3").string();
  }
  static void TearDownTestSuite() { shared_.reset(); }
  SafeFs() : tmp_("bivo_safe_fs_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name())) {
    fs::create_directories(scratch());
  }
  ~SafeFs() override {
    for (const fs::path& m : mounts_) ::umount2(m.c_str(), MNT_DETACH);
  }
  fs::path dir() const { return tmp_.path; }
  fs::path scratch() const { return tmp_.path / "scratch"; }
  static std::string q(const fs::path& p) { return "'" + p.string() + "'"; }
  BivoRun bivo(const std::string& args) const { return bivo::testing::run_bivo_in(args, scratch().string()); }
  // `bivo args` under `sh` with a file size limit of `blocks` x 512 bytes; the signal a
  // write past it raises is ignored, so the write fails with EFBIG as on a full disk.
  BivoRun bivo_with_file_limit(const std::string& args, int blocks) const {
    return bivo::testing::run_bivo_in("--help >/dev/null 2>&1; trap '' XFSZ; ulimit -f " + std::to_string(blocks) +
                                          "; exec '" + BIVO_BINARY + "' " + args,
                                      scratch().string());
  }
  // A tmpfs at `at` with mount options `options`; false when this process may not mount.
  bool mount_tmpfs(const fs::path& at, const std::string& options) {
    fs::create_directories(at);
    if (::mount("none", at.c_str(), "tmpfs", 0, options.c_str()) != 0) return false;
    mounts_.push_back(at);
    return true;
  }
  // Every command that writes a folder, with `out` as that folder.
  std::vector<std::pair<std::string, std::string>> folder_commands(const fs::path& out) const {
    const std::string seq = q(sequence_), o = " --output " + q(out);
    return {{"synth", "synth --category structure_texture_near --frames 2 --supersampling 1" + o},
            {"table", "table --sequences " + seq + " --methods single --levels 2" + o},
            {"pareto", "pareto " + seq + " --pair 0 --points 3 --levels 2 --no-plots" + o},
            {"sweep", "sweep --sequences " + seq + " --lambda-points 2 --eps-points 0 --levels 2" + o},
            {"report", "report --sequences " + seq +
                           " --methods single --lambda-points 0 --eps-points 0 --no-pareto --levels 2 --no-plots" + o}};
  }
  // Plans a one-unit table study; returns its file.
  fs::path plan(const std::string& name, int max_frames) const {
    const fs::path study = dir() / (name + ".json");
    const BivoRun r = bivo("plan table --study " + q(study) + " --sequences " + q(sequence_) +
                           " --methods single --levels 2 --max-frames " + std::to_string(max_frames) + " --output " +
                           q(dir() / (name + ".out")));
    EXPECT_EQ(r.status, 0) << r.err;
    return study;
  }
  static std::string unit_file(const fs::path& study) {
    const auto units = bivo::experiments::study_units(bivo::experiments::read_study(study.string()));
    return bivo::experiments::unit_file_name(units.at(0));
  }

  static std::unique_ptr<bivo::testing::TempDir> shared_;
  static std::string sequence_;
  bivo::testing::TempDir tmp_;
  std::vector<fs::path> mounts_;
};
std::unique_ptr<bivo::testing::TempDir> SafeFs::shared_;
std::string SafeFs::sequence_;

}  // namespace

// An output folder under /proc or where a file stands: "internal error: filesystem error:
// cannot create directories" after all the work.
TEST_F(SafeFs, OutputFolderUnderProcOrWhereAFileStands) {
  std::ofstream(dir() / "afile") << "mine\n";
  for (const auto& [out, why] : {std::pair<fs::path, std::string>{"/proc/bivo_no_such_folder", "No such file"},
                                 {dir() / "afile" / "sub", "is not a folder"}}) {
    for (const auto& [name, args] : folder_commands(out)) {
      expect_clear_error(bivo(args), "--output '" + out.string() + "'");
      EXPECT_TRUE(contains(bivo(args).err, why)) << name;
    }
    expect_clear_error(bivo("run " + q(sequence_) + " --method single --output " + q(out / "t.txt")),
                       (out / "t.txt").string());
  }
  const fs::path study = plan("st", 2);
  expect_clear_error(bivo("work " + q(study) + " --results /proc/bivo_no_such_folder"),
                     "--results '/proc/bivo_no_such_folder'");
  expect_clear_error(bivo("merge " + q(study) + " --output " + q(dir() / "afile")), "exists and is not a folder");
  EXPECT_EQ(slurp(dir() / "afile"), "mine\n");
}

// An output folder on a read-only filesystem.
TEST_F(SafeFs, OutputFolderOnAReadOnlyFilesystem) {
  const fs::path ro = dir() / "ro";
  if (!mount_tmpfs(ro, "size=64k,mode=0755") || ::mount("none", ro.c_str(), nullptr, MS_REMOUNT | MS_RDONLY, "") != 0) {
    GTEST_SKIP() << "cannot mount a read-only tmpfs here (needs root or CAP_SYS_ADMIN)";
  }
  for (const auto& [name, args] : folder_commands(ro / "out")) {
    const BivoRun r = bivo(args);
    expect_clear_error(r, "--output '" + (ro / "out").string() + "' cannot be written");
    EXPECT_TRUE(contains(r.err, "Read-only file system")) << name << ": " << r.err;
  }
  expect_clear_error(bivo("run " + q(sequence_) + " --method single --output " + q(ro / "t.txt")), "Read-only");
  EXPECT_TRUE(fs::is_empty(ro));
}

// A folder the user may not write (permission bits; root ignores them, so skipped as root).
TEST_F(SafeFs, OutputFolderWithoutWritePermission) {
  if (::geteuid() == 0) GTEST_SKIP() << "running as root, which ignores permission bits (see the /proc and ro tests)";
  fs::create_directories(dir() / "locked");
  fs::permissions(dir() / "locked", fs::perms::owner_read | fs::perms::owner_exec);
  for (const auto& [name, args] : folder_commands(dir() / "locked" / "out")) {
    expect_clear_error(bivo(args), "Permission denied");
  }
  fs::permissions(dir() / "locked", fs::perms::owner_all);
  EXPECT_TRUE(fs::is_empty(dir() / "locked"));
}

// A full disk (a file size limit here, and a 24 KiB tmpfs where one can be mounted): synth,
// table and pareto left partial output behind.
TEST_F(SafeFs, FullDiskLeavesNothingPartial) {
  fs::create_directories(dir() / "keep");
  std::ofstream(dir() / "keep" / "mine.txt") << "mine\n";
  for (const auto& [name, args] : folder_commands(dir() / "keep" / "out")) {
    if (name == "sweep" || name == "report") continue;  // the same writers as table and pareto
    const BivoRun r = bivo_with_file_limit(args, 2);
    expect_clear_error(r, "File too large");
    EXPECT_TRUE(contains(r.err, (dir() / "keep" / "out").string())) << name << ": " << r.err;
    std::vector<std::string> left;
    for (const auto& e : fs::recursive_directory_iterator(dir() / "keep")) left.push_back(e.path().string());
    EXPECT_EQ(left, std::vector<std::string>{(dir() / "keep" / "mine.txt").string()}) << name;
  }
  EXPECT_EQ(slurp(dir() / "keep" / "mine.txt"), "mine\n");
  const fs::path full = dir() / "full";
  if (!mount_tmpfs(full, "size=24k")) {
    GTEST_SKIP() << "file size limit tested; cannot mount a small tmpfs here (needs root or CAP_SYS_ADMIN)";
  }
  std::vector<std::string> filled;
  for (const auto& [name, args] : folder_commands(full / "out")) {
    if (name == "sweep" || name == "report") continue;
    fs::remove_all(full / "out");
    const BivoRun r = bivo(args);
    if (r.status == 0) continue;  // small enough to fit
    filled.push_back(name);
    expect_clear_error(r, "No space left on device");
    EXPECT_TRUE(fs::is_empty(full)) << name;
  }
  // A sequence's PNGs and a table's files exceed 24 KiB.
  EXPECT_NE(std::find(filled.begin(), filled.end(), "synth"), filled.end());
  EXPECT_NE(std::find(filled.begin(), filled.end(), "table"), filled.end());
}

// work and merge on a full disk: no partial result file, no partial merged folder.
TEST_F(SafeFs, FullDiskWorkAndMerge) {
  const fs::path study = plan("st", 2);
  const BivoRun w = bivo_with_file_limit("work " + q(study), 1);
  expect_clear_error(w, "File too large");
  EXPECT_TRUE(!fs::exists(dir() / "st.results") || fs::is_empty(dir() / "st.results"));
  ASSERT_EQ(bivo("work " + q(study)).status, 0);
  const BivoRun m = bivo_with_file_limit("merge " + q(study), 2);
  expect_clear_error(m, "File too large");
  EXPECT_FALSE(fs::exists(dir() / "st.out"));
}

// A result file that is a folder: "internal error".
TEST_F(SafeFs, ResultFileIsAFolder) {
  const fs::path study = plan("st", 2);
  const fs::path result = dir() / "st.results" / unit_file(study);
  fs::create_directories(result);
  expect_clear_error(bivo("work " + q(study)), result.string());
  expect_clear_error(bivo("merge " + q(study)), result.string());
  EXPECT_TRUE(fs::is_directory(result));
  EXPECT_FALSE(fs::exists(dir() / "st.out"));
}

// 200,000 nested arrays in a study file and in a merged result payload: SIGSEGV.
TEST_F(SafeFs, NestedArrays200000DeepInStudyAndResultFiles) {
  const std::string deep = std::string(200000, '[') + std::string(200000, ']');
  std::ofstream(dir() / "deep.json") << R"({"format": "bivo-study", "table": )" << deep << "}";
  expect_clear_error(bivo("work " + q(dir() / "deep.json")), "deep.json: values nested more than 64 levels deep");
  expect_clear_error(bivo("merge " + q(dir() / "deep.json")), "deep.json: values nested more than 64 levels deep");
  const fs::path study = plan("st", 2);
  ASSERT_EQ(bivo("work " + q(study)).status, 0);
  const fs::path result = dir() / "st.results" / unit_file(study);
  std::string text = slurp(result);
  const auto at = text.find("\"result\":");
  ASSERT_NE(at, std::string::npos);
  text = text.substr(0, at) + "\"result\":" + deep + "}\n";
  std::ofstream(result) << text;
  const BivoRun m = bivo("merge " + q(study));
  expect_clear_error(m, result.string());
  EXPECT_TRUE(contains(m.err, "nested more than 64")) << m.err;
  EXPECT_LT(m.err.size(), 1000u);
  EXPECT_FALSE(fs::exists(dir() / "st.out"));
  EXPECT_EQ(slurp(result), text);
}

// `bivo work` accepted a result file of another study with the same unit name in its folder.
TEST_F(SafeFs, ForeignResultFileIsRefused) {
  const fs::path a = plan("a", 2), b = plan("b", 3);
  ASSERT_EQ(unit_file(a), unit_file(b));
  ASSERT_EQ(bivo("work " + q(a) + " --results " + q(dir() / "shared.results")).status, 0);
  const fs::path result = dir() / "shared.results" / unit_file(a);
  const std::string before = slurp(result);
  const BivoRun r = bivo("work " + q(b) + " --results " + q(dir() / "shared.results"));
  expect_clear_error(r, "result file '" + result.string() + "' belongs to another study");
  expect_clear_error(bivo("merge " + q(b) + " " + q(dir() / "shared.results")), "belongs to another study");
  EXPECT_EQ(slurp(result), before);
  EXPECT_FALSE(fs::exists(dir() / "b.out"));
}

// A study edited by hand (max_frames changed) ran under its old hash.
TEST_F(SafeFs, HandEditedStudyFailsItsHash) {
  const fs::path study = plan("st", 2);
  std::string text = slurp(study);
  const auto at = text.find("\"max_frames\": 2");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 15, "\"max_frames\": 3");
  std::ofstream(study) << text;
  for (const char* command : {"work ", "merge "}) {
    expect_clear_error(bivo(command + q(study)), study.string() + ": the study was changed after it was planned");
  }
  EXPECT_FALSE(fs::exists(dir() / "st.results"));
}

// A study file without a hash (as an older bivo wrote them) ran unchecked.
TEST_F(SafeFs, StudyWithoutAHashIsRefused) {
  const fs::path study = plan("st", 2);
  nlohmann::json j = nlohmann::json::parse(slurp(study));
  ASSERT_EQ(j.erase("study_hash"), 1u);
  const std::string text = j.dump(2);
  std::ofstream(study) << text;
  for (const char* command : {"work ", "merge "}) {
    const BivoRun r = bivo(command + q(study));
    expect_clear_error(r, study.string() + ": the study has no study_hash");
    EXPECT_TRUE(contains(r.err, "plan it again with `bivo plan`")) << r.err;
  }
  EXPECT_FALSE(fs::exists(dir() / "st.results"));
  EXPECT_FALSE(fs::exists(dir() / "st.out"));
  EXPECT_EQ(slurp(study), text);
}

// VAR 2^30 in a CBF file under --max-conic-size 2^30: std::bad_alloc ("internal error").
// An address-space limit makes the allocation fail at once on every machine.
TEST_F(SafeFs, CbfVar1073741823UnderMaxConicSize1073741824) {
  std::ofstream(dir() / "big.cbf") << "VER\n3\n\nOBJSENSE\nMIN\n\nVAR\n1073741823 1\nF 1073741823\n\nCON\n0 0\n";
  const BivoRun r =
      bivo::testing::run_bivo_in("--help >/dev/null 2>&1; ulimit -v 1000000; exec '" + std::string(BIVO_BINARY) +
                                     "' --max-conic-size 1073741824 conic " + q(dir() / "big.cbf"),
                                 scratch().string());
  expect_clear_error(r, "the problem in '" + (dir() / "big.cbf").string() + "' does not fit in memory");
  EXPECT_TRUE(contains(r.err, "--max-conic-size 1073741824")) << r.err;
}

// An output that is a hard link to the sequence's ground truth (another name, one file).
TEST_F(SafeFs, RunOutputHardLinkedToTheGroundTruth) {
  const fs::path gt = fs::path(sequence_) / "groundtruth.txt";
  const std::string before = slurp(gt);
  fs::create_hard_link(gt, dir() / "linked.txt");
  expect_clear_error(bivo("run " + q(sequence_) + " --method single --output " + q(dir() / "linked.txt")),
                     "is an input of this run");
  EXPECT_EQ(slurp(gt), before);
  EXPECT_EQ(slurp(dir() / "linked.txt"), before);
}

// `table --config out/config.json --output out` replaced its own configuration with the one it
// wrote; a merge into the folder of its study file replaced the study.json it was reading
// (both refused before any work: test_output_collisions.cpp).
TEST_F(SafeFs, OutputsNeverReplaceTheFilesTheyRead) {
  fs::create_directories(dir() / "out");
  const std::string config = "{\"method\": \"single\", \"levels\": 2}\n";
  std::ofstream(dir() / "out" / "config.json") << config;
  const BivoRun t = bivo("table --sequences " + q(sequence_) + " --config " + q(dir() / "out" / "config.json") +
                         " --output " + q(dir() / "out"));
  expect_clear_error(t, "lies in --output");
  EXPECT_EQ(slurp(dir() / "out" / "config.json"), config);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir() / "out"), fs::directory_iterator()), 1);

  const fs::path study = dir() / "merged" / "study.json";
  fs::create_directories(study.parent_path());
  ASSERT_EQ(bivo("plan table --study " + q(study) + " --sequences " + q(sequence_) +
                 " --methods single --levels 2 --max-frames 2 --output " + q(study.parent_path()))
                .status,
            0);
  ASSERT_EQ(bivo("work " + q(study)).status, 0);
  const std::string planned = slurp(study);
  const BivoRun m = bivo("merge " + q(study));
  expect_clear_error(m, "the study '" + study.string() + "', an input of this command, lies in --output");
  EXPECT_EQ(slurp(study), planned);
  std::vector<std::string> left;
  for (const auto& e : fs::directory_iterator(study.parent_path())) left.push_back(e.path().filename().string());
  std::sort(left.begin(), left.end());
  EXPECT_EQ(left, (std::vector<std::string>{"study.json", "study.results"}));
}
