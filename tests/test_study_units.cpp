// The study layer without running the tracker: the study file (round trip, strictness),
// its hash, unit ids, shards (disjoint, complete, deterministic), unit results read back
// bit for bit, the sweep assembled from unit results, the RPE units of tables and sweeps,
// and the Slurm / GNU Parallel text.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <set>

#include <gtest/gtest.h>

#include "experiments/method_matrix.h"
#include "experiments/parameter_sweep.h"
#include "experiments/study/study.h"
#include "experiments/study/study_launch.h"
#include "experiments/study/study_results.h"
#include "experiments/study/study_work.h"
#include "experiments/trajectory_evaluation.h"
#include "solvers/error.h"
#include "test_support.h"

using namespace bivo;
using namespace bivo::experiments;
using bivo::testing::error_of;

namespace {

Study report_study_by_hand() {
  Study s;
  s.kind = "report";
  s.output = "/tmp/out";
  s.tracker.levels = 3;
  s.tracker.policy.lambda = 0.1 + 0.2;  // not a short decimal: must survive bit for bit
  MatrixOptions t;
  t.sequences = {"/data/rgbd_dataset_freiburg1_rpy", "/data/teddy"};
  t.methods = {{"single", ""}, {"bounded", "ipm-full"}};
  t.max_frames = 30;
  s.table = t;
  SweepOptions w;
  w.sequences = {"/data/teddy"};
  w.lambdas = {100, 1e4};
  w.epsilons = {1e-3};
  w.max_frames = 20;
  s.sweep = w;
  ParetoPlan p;
  p.options.points = 5;
  p.options.methods = {"single", "bounded"};
  p.pairs = {{"/data/teddy", 9}};
  s.pareto = p;
  s.report = ReportText{"T", "P"};
  return s;
}

}  // namespace

TEST(StudyFile, RoundTripsBitForBitAndIsStrict) {
  const Study s = report_study_by_hand();
  const nlohmann::json j = study_to_json(s);
  const Study back = study_from_json(nlohmann::json::parse(j.dump()), "s.json");
  EXPECT_EQ(study_to_json(back), j);
  EXPECT_EQ(back.tracker.policy.lambda, 0.1 + 0.2);
  EXPECT_EQ(back.table->methods[1].backend, "ipm-full");
  EXPECT_EQ(back.pareto->pairs[0].pair, 9);

  nlohmann::json unhashed = j;
  unhashed.erase("study_hash");
  EXPECT_NE(error_of([&] { study_from_json(unhashed, "s.json"); }).find("s.json: the study has no study_hash"),
            std::string::npos);
  nlohmann::json typo = j;
  typo["table"]["sequencs"] = typo["table"]["sequences"];
  EXPECT_NE(error_of([&] { study_from_json(typo, "s.json"); }).find("s.json.table: unknown key 'sequencs'"),
            std::string::npos);
  nlohmann::json bad_tracker = j;
  bad_tracker["tracker"]["levels"] = 0;
  EXPECT_NE(
      error_of([&] { study_from_json(bad_tracker, "s.json"); }).find("s.json.tracker: levels: 0 is outside [1, 8]"),
      std::string::npos);
  nlohmann::json table_kind = j;
  table_kind["kind"] = "table";
  EXPECT_NE(error_of([&] { study_from_json(table_kind, "s.json"); }).find("has no 'sweep' part"), std::string::npos);
  nlohmann::json bad_method = j;
  bad_method["table"]["methods"][0] = "sideways";
  EXPECT_NE(error_of([&] { study_from_json(bad_method, "s.json"); }).find("sideways"), std::string::npos);
}

TEST(StudyFile, HashCoversWhatUnitsComputeOnly) {
  const Study s = report_study_by_hand();
  const std::string h = study_hash(s);
  EXPECT_EQ(h.size(), 16u);
  Study same = s;
  same.output = "/elsewhere";
  same.seed = 99;
  same.plots = false;
  same.report->title = "another title";
  EXPECT_EQ(study_hash(same), h);
  Study other = s;
  other.sweep->lambdas[1] = std::nextafter(1e4, 2e4);
  EXPECT_NE(study_hash(other), h);
  other = s;
  other.tracker.max_iterations += 1;
  EXPECT_NE(study_hash(other), h);
}

TEST(StudyUnits, AreNamedAndOrderedTableSweepPareto) {
  const std::vector<StudyUnit> units = study_units(report_study_by_hand());
  std::vector<std::string> ids;
  for (const auto& u : units) ids.push_back(u.id);
  const std::vector<std::string> want = {
      "table/0-single/0-freiburg1_rpy",   "table/0-single/1-teddy",        "table/1-bounded_ipm-full/0-freiburg1_rpy",
      "table/1-bounded_ipm-full/1-teddy", "sweep/0-teddy/single",          "sweep/0-teddy/lambda-0=100",
      "sweep/0-teddy/lambda-1=10000",     "sweep/0-teddy/epsilon-0=0.001", "pareto/0-teddy/pair-9"};
  EXPECT_EQ(ids, want);
  EXPECT_EQ(units[3].item, 3);  // method 1 x 2 sequences + sequence 1
  EXPECT_EQ(units[8].part, "pareto");
  EXPECT_EQ(unit_file_name(units[5]), "u00005_sweep_0-teddy_lambda-0=100.json");
}

TEST(StudyShards, AreDisjointCompleteAndDeterministic) {
  const Study s = report_study_by_hand();
  const int n = int(study_units(s).size());
  for (int shards = 1; shards <= n + 2; ++shards) {
    std::multiset<int> seen;
    for (int i = 0; i < shards; ++i) {
      const auto a = shard_units(s, {i, shards}), b = shard_units(s, {i, shards});
      ASSERT_EQ(a.size(), b.size());
      for (size_t k = 0; k < a.size(); ++k) EXPECT_EQ(a[k].id, b[k].id);
      for (const auto& u : a) seen.insert(u.index);
      EXPECT_LE(int(a.size()), (n + shards - 1) / shards);  // dealt round-robin: balanced counts
    }
    EXPECT_EQ(int(seen.size()), n);
    for (int k = 0; k < n; ++k) EXPECT_EQ(seen.count(k), 1u) << "unit " << k << " with " << shards << " shards";
  }
  // Another seed deals another permutation (for this study and these seeds).
  Study reseeded = s;
  reseeded.seed = 2;
  std::vector<int> a, b;
  for (const auto& u : shard_units(s, {0, 3})) a.push_back(u.index);
  for (const auto& u : shard_units(reseeded, {0, 3})) b.push_back(u.index);
  EXPECT_NE(a, b);
}

TEST(StudyShards, ShardSpecIsIOfN) {
  EXPECT_EQ(parse_shard("2/3").index, 2);
  EXPECT_EQ(parse_shard("2/3").count, 3);
  for (const char* bad : {"3/3", "-1/3", "a/b", "1/0", "1/3x", "1"}) {
    EXPECT_NE(error_of([&] { parse_shard(bad); }).find(bad), std::string::npos) << bad;
  }
}

TEST(UnitResults, MatrixCellReadsBackBitForBit) {
  MatrixCell c;
  c.sequence_dir = "/d/s";
  c.sequence = "s";
  c.spec = {"bounded", "ipm-full"};
  c.backend = "ipm-full";
  RunOutcome run;
  run.sequence = "s";
  run.method = "bounded";
  run.backend = "ipm-full";
  odometry::io::Trajectory gt;
  for (int k = 0; k <= 1000; ++k) gt.push_back({0.125 * k, Eigen::Isometry3d::Identity()});
  run.groundtruth = gt;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.rotate(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()));
  T.translation() << 1.0 / 3.0, -2e-7, 5.5;
  run.trajectory = {{10.0, Eigen::Isometry3d::Identity()}, {10.0 + 1.0 / 30.0, T}};
  odometry::PairResult p;
  p.T_21 = T;
  p.T_wc = T;
  p.mu = std::numeric_limits<double>::infinity();  // infeasible bound
  p.seconds = 0.0123456789012345;
  p.profile.add("residuals", 1.0 / 7.0);
  odometry::LevelResult level;
  level.mu = -std::numeric_limits<double>::infinity();
  level.f_i = std::nan("");
  level.termination = "step";
  p.levels = {level};
  p.error = odometry::io::PoseError{1e-3 / 3.0, 0.25};
  run.pairs = {p};
  run.median_ms = 12.345678901234567;
  c.run = run;
  c.rpe = odometry::io::RpeResult{};
  c.rpe->trans_rmse = 2.0 / 3.0;
  c.rpe->pairs = {{1, 2, 3, 4, 5, 6}};
  c.note = "no ATE: too short";

  const nlohmann::json j = matrix_cell_to_json(c);
  const MatrixCell back = matrix_cell_from_json(nlohmann::json::parse(j.dump()));
  EXPECT_EQ(matrix_cell_to_json(back).dump(), j.dump());
  EXPECT_TRUE(back.run->trajectory[1].T_wc.matrix() == T.matrix());
  EXPECT_EQ(back.run->pairs[0].mu, std::numeric_limits<double>::infinity());
  EXPECT_EQ(back.run->pairs[0].levels[0].mu, -std::numeric_limits<double>::infinity());
  EXPECT_TRUE(std::isnan(back.run->pairs[0].levels[0].f_i));
  EXPECT_EQ(back.run->pairs[0].seconds, p.seconds);
  EXPECT_EQ(back.run->pairs[0].profile.seconds("residuals"), 1.0 / 7.0);
  EXPECT_EQ(back.rpe->trans_rmse, 2.0 / 3.0);
  EXPECT_FALSE(back.ate.has_value());
  // The ground truth is kept within 1 s of the window [10, 10.033]: stamps 9.0 .. 11.0.
  ASSERT_TRUE(back.run->groundtruth.has_value());
  EXPECT_EQ(back.run->groundtruth->size(), 17u);
  EXPECT_EQ(back.run->groundtruth->front().timestamp, 9.0);
  EXPECT_EQ(back.run->groundtruth->back().timestamp, 11.0);
}

TEST(UnitResults, ParetoOutcomeReadsBack) {
  ParetoOutcome o;
  ParetoStudy s;
  s.sequence = "teddy";
  s.pair = 4;
  StudyPoint a;
  a.f_i = 1.0 / 3.0;
  a.f_d = 2e-5;
  a.parameter = 1e5;
  a.error = odometry::io::PoseError{0.001, 0.1};
  s.lambda_front = {a};
  a.method = "bounded";
  s.methods = {a};
  s.knee = a;
  o.study = s;
  const nlohmann::json j = pareto_outcome_to_json(o);
  EXPECT_EQ(pareto_outcome_to_json(pareto_outcome_from_json(nlohmann::json::parse(j.dump()))).dump(), j.dump());
  EXPECT_EQ(pareto_json(*pareto_outcome_from_json(j).study), pareto_json(s));
  EXPECT_EQ(pareto_outcome_from_json(pareto_outcome_to_json({std::nullopt, "pair 99 outside"})).error,
            "pair 99 outside");
}

TEST(SweepAssembly, RatiosToTheReferenceAndNotes) {
  SweepOptions o;
  o.sequences = {"/d/a", "/d/b"};
  o.lambdas = {10, 100};
  const std::vector<SweepUnit> units = sweep_units(o);
  ASSERT_EQ(units.size(), 6u);
  auto ok = [](const SweepUnit& u, double rmse, double max) {
    SweepRun r;
    r.unit = u;
    r.sequence = "rgbd_dataset_a";
    r.ok = true;
    r.rpe_trans = rmse;
    r.max_err = max;
    return r;
  };
  std::vector<SweepRun> runs = {ok(units[0], 0.2, 0.4), ok(units[1], 0.1, 0.1), ok(units[2], 0.3, 0.8)};
  SweepRun failed;
  failed.unit = units[3];
  failed.sequence = "b";
  failed.missing = true;  // b's reference never ran: its points are left out
  runs.push_back(failed);
  runs.push_back(ok(units[4], 1, 1));
  runs.push_back(ok(units[5], 1, 1));
  const SweepResult r = assemble_sweep(o, runs);
  ASSERT_EQ(r.points.size(), 2u);
  EXPECT_EQ(r.points[0].sequence, "a");
  EXPECT_DOUBLE_EQ(r.points[0].rmse_ratio, 0.5);
  EXPECT_DOUBLE_EQ(r.points[1].max_ratio, 2.0);
  ASSERT_EQ(r.notes.size(), 1u);
  EXPECT_NE(r.notes[0].find("reference was not run"), std::string::npos);

  runs[3].missing = false;
  runs[3].error = "sweep: sequence '/d/b' has no groundtruth.txt";
  // A failed reference leaves its sequence's points out with a note; the others are kept.
  const SweepResult without_b = assemble_sweep(o, runs);
  EXPECT_EQ(without_b.points.size(), 2u);
  ASSERT_EQ(without_b.notes.size(), 1u);
  EXPECT_EQ(without_b.notes[0],
            "b: the single-objective reference failed (" + runs[3].error + "); its points are left out");
  runs[3] = ok(units[3], 0.5, 0.5);
  runs[4].ok = false;
  runs[4].error = "diverged";
  EXPECT_EQ(assemble_sweep(o, runs).notes, std::vector<std::string>{"rgbd_dataset_a lambda=10: diverged"});
}

TEST(StudyLaunch, SlurmArrayAndGnuParallelCommandLines) {
  EXPECT_EQ(shell_quote("/a/b-c_1.json"), "/a/b-c_1.json");
  EXPECT_EQ(shell_quote("a b'c"), "'a b'\\''c'");
  LaunchOptions o;
  o.bivo = "/opt/bivo";
  o.study_path = "/s/study.json";
  o.results_dir = "/s/study results";
  o.shards = 4;
  o.throttle = 2;
  o.threads = 3;
  o.log_dir = "/s/logs";
  o.sbatch_args = {"--mem=4G"};
  const std::string array = slurm_array_script(o, "/s/study.submit.sh");
  EXPECT_NE(array.find("#SBATCH --array=0-3%2\n"), std::string::npos) << array;
  EXPECT_NE(array.find("#SBATCH --cpus-per-task=3\n"), std::string::npos) << array;
  EXPECT_NE(array.find("#SBATCH --mem=4G\n"), std::string::npos) << array;
  EXPECT_NE(
      array.find("exec /opt/bivo work /s/study.json --shard \"${SLURM_ARRAY_TASK_ID}/4\" --results '/s/study results'"),
      std::string::npos)
      << array;
  const std::string submit = slurm_submit_script(o, "/s/study.sbatch");
  EXPECT_NE(submit.find("--dependency=afterok:${array}"), std::string::npos) << submit;
  EXPECT_NE(submit.find("--kill-on-invalid-dep=yes"), std::string::npos) << submit;
  o.jobs = 2;
  o.sshlogins = {"8/node1", ":"};
  EXPECT_EQ(parallel_command(o),
            "parallel --quote --halt never --jobs 2 --sshlogin 8/node1 --sshlogin : /opt/bivo work /s/study.json "
            "--shard {}/4 --results '/s/study results' ::: $(seq 0 3) && /opt/bivo merge /s/study.json "
            "'/s/study results'\n");
  o.log_dir = "/with space";
  EXPECT_NE(error_of([&] { slurm_array_script(o, "x"); }).find("/with space"), std::string::npos);
}

// RPE is per window: a table or sweep over windows other than 1 s must not say m/s.
TEST(RpeUnits, TablesAndSweepsNameTheirWindow) {
  EXPECT_EQ(rpe_unit("m", 1.0), "m/s");
  EXPECT_EQ(rpe_unit("deg", 0.5), "deg per 0.5 s");
  EXPECT_EQ(rpe_windows(1.0), "1-s windows");
  MatrixOptions o;
  o.sequences = {"/d/rgbd_dataset_a"};
  o.methods = {{"single", ""}};
  MatrixCell c;
  c.sequence = "a";
  c.spec = o.methods[0];
  c.rpe = odometry::io::RpeResult{};
  for (const double delta : {1.0, 0.5}) {
    o.rpe_delta = delta;
    const std::string md = matrix_markdown(assemble_matrix(o, {c}));
    const bool per_second = delta == 1.0;
    EXPECT_EQ(md.find("over 1-s windows [m/s]") != std::string::npos, per_second) << md;
    EXPECT_EQ(md.find("| RPE rot [deg/s] |") != std::string::npos, per_second) << md;
    EXPECT_EQ(md.find("over 0.5-s windows [m per 0.5 s]") != std::string::npos, !per_second) << md;
    EXPECT_EQ(md.find("| RPE rot [deg per 0.5 s] |") != std::string::npos, !per_second) << md;
  }
  SweepOptions w;
  w.sequences = {"/d/a"};
  w.lambdas = {10};
  w.rpe_delta = 0.25;
  std::vector<SweepRun> runs;
  for (const SweepUnit& u : sweep_units(w)) {
    SweepRun r;
    r.unit = u;
    r.sequence = "a";
    r.ok = true;
    r.rpe_trans = r.max_err = 0.1;
    runs.push_back(r);
  }
  const std::string dir = ::testing::TempDir() + "/bivo_rpe_units_sweep";
  write_sweep(assemble_sweep(w, runs), dir);
  std::ifstream in(dir + "/sweep.md");
  const std::string md((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(md.find("| RPE trans [m per 0.25 s] | max [m per 0.25 s] |"), std::string::npos) << md;
  std::filesystem::remove_all(dir);
}
