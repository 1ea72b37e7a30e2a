// Leave-one-sequence-out as a study (experiments/study/study.h, kind "loso"): its file reads
// back bit for bit and its hash covers what the runs compute (one parameter: the part as it
// always was); `bivo plan loso` refuses a bad parameter, grid or finest level before anything
// runs; and two shards merged give the files of `bivo loso` in one process, on two tiny
// rendered sequences (8 runs of 5 frames at the coarsest levels; with two parameters at two
// pooled finest levels, 20).
#include <algorithm>
#include <cmath>
#include <limits>

#include "experiments/study/study.h"
#include "experiments/study/study_results.h"
#include "solvers/error.h"
#include "study_test_support.h"

namespace fs = std::filesystem;
using namespace bivo::experiments;
using namespace bivo::testing;

namespace {

Study loso_study_by_hand() {
  Study s;
  s.kind = "loso";
  s.output = "/tmp/loso";
  s.tracker.levels = 3;
  LosoOptions o;
  o.sequences = {"/data/a/rgbd_dataset_freiburg1_rpy", "/data/b/teddy", "/data/c/teddy"};
  o.method = "robust";
  o.parameters = {{"trust", {300, 0.1 + 0.2, 1e12}}};  // 0.1 + 0.2: not a short decimal, must survive bit for bit
  o.reference = "single";
  o.methods = {"weighted", "joint"};
  o.first_frame = 2;
  o.max_frames = 40;
  s.loso = o;
  return s;
}

// The CSV without its column `name` (a timing: it differs from run to run).
std::string without_column(const std::string& csv, const std::string& name) {
  std::istringstream in(csv);
  std::string line, out;
  int drop = -1;
  while (std::getline(in, line)) {
    std::vector<std::string> fields;
    std::stringstream ls(line);
    for (std::string f; std::getline(ls, f, ',');) fields.push_back(f);
    if (drop < 0) drop = int(std::find(fields.begin(), fields.end(), name) - fields.begin());
    for (int k = 0; k < int(fields.size()); ++k) {
      if (k != drop) out += fields[k] + ",";
    }
    out += "\n";
  }
  return out;
}

}  // namespace

TEST(LosoStudy, FileRoundTripsAndTheHashCoversTheLosoPart) {
  const Study s = loso_study_by_hand();
  check_study(s);
  const nlohmann::json j = study_to_json(s);
  const Study back = study_from_json(nlohmann::json::parse(j.dump()), "s.json");
  EXPECT_EQ(study_to_json(back), j);
  ASSERT_TRUE(back.loso);
  EXPECT_EQ(back.loso->parameters[0].grid[1], 0.1 + 0.2);
  EXPECT_EQ(back.loso->methods, s.loso->methods);
  EXPECT_EQ(back.loso->first_frame, 2);
  EXPECT_EQ(back.loso->max_frames, 40);
  // Per sequence: the reference, 3 grid values, 2 fixed methods; ids name all of it.
  const std::vector<StudyUnit> units = study_units(back);
  ASSERT_EQ(units.size(), 18u);
  EXPECT_EQ(units[0].id, "loso/0-freiburg1_rpy/single");
  EXPECT_EQ(units[2].id, "loso/0-freiburg1_rpy/robust/trust-1=0.3");
  EXPECT_EQ(units[11].id, "loso/1-teddy/joint");  // the index keeps the two "teddy" folders apart
  EXPECT_EQ(units[17].id, "loso/2-teddy/joint");

  // What the runs compute changes the hash; where the outputs go does not.
  const std::string h = study_hash(s);
  const auto hash_with = [&](auto change) {
    Study t = s;
    change(t);
    return study_hash(t);
  };
  EXPECT_EQ(hash_with([](Study& t) { t.output = "/elsewhere"; }), h);
  EXPECT_EQ(hash_with([](Study& t) { t.seed = 7; }), h);
  EXPECT_NE(hash_with([](Study& t) { t.loso->sequences.pop_back(); }), h);
  EXPECT_NE(hash_with([](Study& t) { t.loso->method = "joint"; }), h);
  EXPECT_NE(hash_with([](Study& t) { t.loso->parameters[0].name = "kappa"; }), h);
  EXPECT_NE(hash_with([](Study& t) { t.loso->parameters[0].grid[0] = 301; }), h);
  EXPECT_NE(hash_with([](Study& t) { t.loso->reference = "weighted"; }), h);
  EXPECT_NE(hash_with([](Study& t) { t.loso->methods.pop_back(); }), h);
  EXPECT_NE(hash_with([](Study& t) { t.loso->first_frame = 3; }), h);
  EXPECT_NE(hash_with([](Study& t) { t.loso->max_frames = 41; }), h);
  EXPECT_NE(hash_with([](Study& t) { t.tracker.levels = 4; }), h);
  // One parameter is written as before several could be chosen together: the same part, so
  // the same hash for studies planned before (and their results merge).
  std::vector<std::string> keys;
  for (auto it = j["loso"].begin(); it != j["loso"].end(); ++it) keys.push_back(it.key());
  EXPECT_EQ(keys, (std::vector<std::string>{"acceptable_ratio", "first_frame", "grid", "max_frames", "method",
                                            "methods", "parameter", "reference", "sequences"}));
  // The acceptable ratio chooses among finished runs too; a file without it (planned before
  // the rule) merges as it was planned: the smallest worst ratio decides.
  EXPECT_EQ(j["loso"]["acceptable_ratio"], 1.05);
  EXPECT_EQ(hash_with([](Study& t) { t.loso->acceptable_ratio = 0.0; }), h);
  nlohmann::json before_rule = j;
  before_rule["loso"].erase("acceptable_ratio");
  EXPECT_EQ(study_from_json(before_rule, "s.json").loso->acceptable_ratio, 0.0);
  nlohmann::json negative = j;
  negative["loso"]["acceptable_ratio"] = -1.0;
  EXPECT_NE(error_of([&] { study_from_json(negative, "s.json"); }).find("acceptable_ratio"), std::string::npos);
  // The RPE window scores every run: hashed, absent at its default of 1 s, read back.
  EXPECT_EQ(j["loso"].count("rpe_delta"), 0u);
  EXPECT_NE(hash_with([](Study& t) { t.loso->rpe_delta = 0.5; }), h);
  Study windowed = s;
  windowed.loso->rpe_delta = 0.5;
  EXPECT_EQ(study_from_json(nlohmann::json::parse(study_to_json(windowed).dump()), "s.json").loso->rpe_delta, 0.5);
  nlohmann::json zero_window = j;
  zero_window["loso"]["rpe_delta"] = 0.0;
  EXPECT_NE(error_of([&] { study_from_json(zero_window, "s.json"); }).find("rpe_delta"), std::string::npos);
  // A cost budget chooses among finished runs: the same runs merge under any budget.
  EXPECT_EQ(j["loso"].count("cost_budget"), 0u);  // none: the file of a study planned without one
  Study budgeted = s;
  budgeted.loso->cost_budget = 1.3;
  budgeted.loso->cost_method = "joint";
  EXPECT_EQ(study_hash(budgeted), h);
  const Study budget_back = study_from_json(nlohmann::json::parse(study_to_json(budgeted).dump()), "s.json");
  EXPECT_EQ(budget_back.loso->cost_budget, 1.3);
  EXPECT_EQ(budget_back.loso->cost_method, "joint");
  budgeted.loso->cost_method = "depth";  // not run
  EXPECT_NE(error_of([&] { check_study(budgeted); }).find("'depth', which is neither"), std::string::npos);

  // Strict: an unknown key, a part of another kind, a bad parameter or method are refused.
  nlohmann::json typo = j;
  typo["loso"]["grdi"] = typo["loso"]["grid"];
  EXPECT_NE(error_of([&] { study_from_json(typo, "s.json"); }).find("s.json.loso: unknown key 'grdi'"),
            std::string::npos);
  nlohmann::json table_kind = j;
  table_kind["kind"] = "table";
  EXPECT_NE(error_of([&] { study_from_json(table_kind, "s.json"); }).find("needs a 'table' part"), std::string::npos);
  table_kind["kind"] = "lsoo";
  EXPECT_NE(error_of([&] { study_from_json(table_kind, "s.json"); }).find("valid: table, sweep, pareto, report, loso"),
            std::string::npos);
  nlohmann::json bad = j;
  bad["loso"]["parameter"] = "no_such_option";
  EXPECT_NE(error_of([&] { study_from_json(bad, "s.json"); }).find("no_such_option"), std::string::npos);
  bad = j;
  bad["loso"]["methods"][1] = "sideways";
  EXPECT_NE(error_of([&] { study_from_json(bad, "s.json"); }).find("sideways"), std::string::npos);
  Study infinite = s;  // JSON has no infinity: refused when planned, not when read back
  infinite.loso->parameters[0].grid[2] = std::numeric_limits<double>::infinity();
  EXPECT_NE(error_of([&] { check_study(infinite); }).find("not finite"), std::string::npos);
  Study twice = s;
  twice.loso->methods[1] = "single";  // the reference twice: two units of one name
  EXPECT_NE(error_of([&] { study_units(study_from_json(study_to_json(twice), "s.json")); }).find("two units named"),
            std::string::npos);
}

TEST(LosoStudy, SeveralParametersAndPooledLevelsRoundTripAndAreHashed) {
  Study s = loso_study_by_hand();
  s.loso->parameters = {{"trust", {300, 0.1 + 0.2}}, {"robust_kappa", {0.2, 0.3}}};
  s.loso->finest_levels = {1, 2};
  check_study(s);
  const nlohmann::json j = study_to_json(s);
  EXPECT_EQ(j["loso"].count("parameter") + j["loso"].count("grid"), 0u);
  EXPECT_EQ(j["loso"]["parameters"][1]["parameter"], "robust_kappa");
  EXPECT_EQ(j["loso"]["finest_levels"], nlohmann::json({1, 2}));
  const Study back = study_from_json(nlohmann::json::parse(j.dump()), "s.json");
  EXPECT_EQ(study_to_json(back), j);
  ASSERT_EQ(back.loso->parameters.size(), 2u);
  EXPECT_EQ(back.loso->parameters[0].grid[1], 0.1 + 0.2);
  EXPECT_EQ(back.loso->finest_levels, (std::vector<int>{1, 2}));
  // Per sequence and level: the reference, 2 x 2 settings, 2 fixed methods.
  const std::vector<StudyUnit> units = study_units(back);
  ASSERT_EQ(units.size(), 3u * 2u * 7u);
  EXPECT_EQ(units[0].id, "loso/0-freiburg1_rpy/single/finest-1");
  EXPECT_EQ(units[2].id, "loso/0-freiburg1_rpy/robust/trust-0=300/robust_kappa-1=0.3/finest-1");
  EXPECT_EQ(units[4].id, "loso/0-freiburg1_rpy/robust/trust-1=0.3/robust_kappa-1=0.3/finest-1");
  EXPECT_EQ(units[13].id, "loso/0-freiburg1_rpy/joint/finest-2");

  const std::string h = study_hash(s);
  EXPECT_NE(h, study_hash(loso_study_by_hand()));
  const auto hash_with = [&](auto change) {
    Study t = s;
    change(t);
    return study_hash(t);
  };
  EXPECT_NE(hash_with([](Study& t) { t.loso->parameters[1].grid[0] = 0.25; }), h);
  EXPECT_NE(hash_with([](Study& t) { std::swap(t.loso->parameters[0], t.loso->parameters[1]); }), h);
  EXPECT_NE(hash_with([](Study& t) { t.loso->finest_levels = {1}; }), h);
  EXPECT_NE(hash_with([](Study& t) { t.loso->finest_levels.clear(); }), h);
  EXPECT_EQ(hash_with([](Study& t) { t.loso->cost_budget = 1.3; }), h);

  // Refused in the file: both forms at once, no levels, a level the pyramid lacks (3 levels),
  // a level twice, an unknown key in a parameter.
  nlohmann::json bad = j;
  bad["loso"]["parameter"] = "trust";
  bad["loso"]["grid"] = {1};
  EXPECT_NE(error_of([&] { study_from_json(bad, "s.json"); }).find("either 'parameters' or 'parameter' and 'grid'"),
            std::string::npos);
  bad = j;
  bad["loso"]["finest_levels"] = nlohmann::json::array();
  EXPECT_NE(error_of([&] { study_from_json(bad, "s.json"); }).find("s.json.loso.finest_levels: must be a non-empty"),
            std::string::npos);
  bad["loso"]["finest_levels"] = {1, 3};
  EXPECT_NE(error_of([&] { study_from_json(bad, "s.json"); }).find("--finest-levels 3 is not a level"),
            std::string::npos);
  bad["loso"]["finest_levels"] = {2, 2};
  EXPECT_NE(error_of([&] { study_from_json(bad, "s.json"); }).find("lists 2 twice"), std::string::npos);
  bad = j;
  bad["loso"]["parameters"][0]["grdi"] = {1};
  EXPECT_NE(error_of([&] { study_from_json(bad, "s.json"); }).find("s.json.loso.parameters[0]: unknown key 'grdi'"),
            std::string::npos);
}

TEST(LosoStudy, ARunReadsBackBitForBit) {
  LosoRun r;
  r.sequence = 1;
  r.method = "robust";
  r.values = {0.1 + 0.2};
  r.ok = true;
  r.sequence_name = "teddy";
  r.rpe_trans = 1.0 / 3.0;
  r.rpe_rot = std::nextafter(2.0, 3.0);
  r.median_cpu_ms = 12.5;
  r.pair_trans = {0.1, 1e-300};
  r.pair_rot = {std::numeric_limits<double>::infinity(), 0.7};
  const LosoRun back = loso_run_from_json(nlohmann::json::parse(loso_run_to_json(r).dump()));
  EXPECT_EQ(back.sequence, 1);
  EXPECT_EQ(back.method, "robust");
  EXPECT_EQ(back.values, r.values);
  EXPECT_EQ(back.finest_level, -1);
  // A run at a setting of two parameters and a pooled finest level.
  r.values = {0.1 + 0.2, 3.0};
  r.finest_level = 1;
  const LosoRun two = loso_run_from_json(nlohmann::json::parse(loso_run_to_json(r).dump()));
  EXPECT_EQ(two.values, r.values);
  EXPECT_EQ(two.finest_level, 1);
  // A fixed method's run keeps no values.
  r.values.clear();
  EXPECT_TRUE(loso_run_from_json(loso_run_to_json(r)).values.empty());
  EXPECT_TRUE(back.ok);
  EXPECT_EQ(back.sequence_name, "teddy");
  EXPECT_EQ(back.rpe_trans, r.rpe_trans);
  EXPECT_EQ(back.rpe_rot, r.rpe_rot);
  EXPECT_EQ(back.median_cpu_ms, 12.5);
  EXPECT_EQ(back.pair_trans, r.pair_trans);
  EXPECT_EQ(back.pair_rot, r.pair_rot);
}

TEST(LosoStudy, ABadParameterIsRefusedWhenPlanned) {
  const TempDir temp("bivo_loso_plan");
  const fs::path& root = temp.path;
  // Planning reads no data: the sequences need not exist.
  const std::string flags = " --sequences /data/a /data/b --method robust --output " + q(root / "out") + " --study ";
  Shell r = shell(bivo_cli() + " plan loso" + flags + q(root / "bad.json") + " --parameter no_such --grid 1 2", root);
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("'no_such' is not a numeric tracker option"), std::string::npos) << r.err;
  // A value outside the option's range: depth_noise_exponent is an integer in [0, 3].
  r = shell(
      bivo_cli() + " plan loso" + flags + q(root / "bad.json") + " --parameter problem.depth_noise_exponent --grid 0 4",
      root);
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("depth_noise_exponent"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(root / "bad.json"));
  r = shell(bivo_cli() + " plan loso" + flags + q(root / "good.json") + " --parameter trust --grid 100 1000", root);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("loso study, 6 unit(s)"), std::string::npos) << r.err;
  // A cost budget in units of a method that does not run is refused; with it, the file keeps it.
  r = shell(bivo_cli() + " plan loso" + flags + q(root / "budget.json") + " --parameter trust --grid 100 1000" +
                " --cost-budget 1.3",
            root);
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("'weighted', which is neither the reference nor among the methods"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(root / "budget.json"));
  r = shell(bivo_cli() + " plan loso" + flags + q(root / "budget.json") + " --parameter trust --grid 100 1000" +
                " --methods weighted --cost-budget -1",
            root);
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("cost budget must be finite and >= 0 (0: none), got -1"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(root / "budget.json"));
  r = shell(bivo_cli() + " plan loso" + flags + q(root / "budget.json") + " --parameter trust --grid 100 1000" +
                " --acceptable-ratio -2",
            root);
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("acceptable ratio must be finite and >= 0 (0: the smallest worst ratio decides), got -2"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(root / "budget.json"));
  r = shell(bivo_cli() + " plan loso" + flags + q(root / "budget.json") + " --parameter trust --grid 100 1000" +
                " --methods weighted --cost-budget 1.3",
            root);
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json planned = nlohmann::json::parse(slurp(root / "budget.json"));
  EXPECT_EQ(planned["loso"]["cost_budget"], 1.3);
  EXPECT_EQ(planned["loso"]["cost_method"], "weighted");
}

TEST(LosoStudy, TwoShardsMergeToTheFilesOfOneProcess) {
  const TempDir temp("bivo_loso_study");
  const fs::path& root = temp.path;
  const std::vector<std::string> sequences = render_test_sequences(root / "sequences");
  std::string flags = "--sequences";
  for (const auto& s : sequences) flags += " " + q(s);
  flags +=
      " --method robust --parameter trust --grid 100 1e12 --methods weighted --max-frames 5 --levels 4"
      " --finest-level 3 --output ";

  const Shell one = shell(bivo_cli() + " loso " + flags + q(root / "one"), root);
  ASSERT_EQ(one.status, 0) << one.err;
  const fs::path study = root / "study.json", results = root / "results";
  Shell r = shell(bivo_cli() + " plan loso " + flags + q(root / "merged") + " --study " + q(study), root);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("8 unit(s)"), std::string::npos) << r.err;
  for (const char* shard : {"0/2", "1/2"}) {
    r = shell(bivo_cli() + " work " + q(study) + " --shard " + shard + " --results " + q(results), root);
    ASSERT_EQ(r.status, 0) << r.err;
  }
  EXPECT_EQ(result_files(results), 8);
  const Shell m = shell(bivo_cli() + " merge " + q(study) + " " + q(results), root);
  ASSERT_EQ(m.status, 0) << m.err;
  EXPECT_EQ(m.out, one.out);  // the held-out table, as `bivo loso` prints it

  // Not two failures comparing equal: every run succeeded and both rows have numbers.
  const std::string md = slurp(root / "one" / "loso.md");
  EXPECT_EQ(md.find("failed"), std::string::npos) << md;
  for (const auto& s : sequences) EXPECT_NE(md.find("| " + fs::path(s).filename().string() + " |"), std::string::npos);
  const std::string runs = slurp(root / "one" / "runs.csv");
  EXPECT_EQ(std::count(runs.begin(), runs.end(), '\n'), 9) << runs;  // a header and 8 runs
  for (const char* exact : {"loso.md", "loso.csv", "pairs.csv", "config.json"}) {
    EXPECT_EQ(slurp(root / "one" / exact), slurp(root / "merged" / exact)) << exact;
  }
  EXPECT_EQ(without_column(slurp(root / "one" / "runs.csv"), "median_cpu_ms"),
            without_column(slurp(root / "merged" / "runs.csv"), "median_cpu_ms"));

  // Results of another study (here: another grid) are refused, naming the file.
  const fs::path other = root / "other.json";
  std::string other_flags = flags;
  other_flags.replace(other_flags.find("--grid 100"), 10, "--grid 300");
  r = shell(bivo_cli() + " plan loso " + other_flags + q(root / "other") + " --study " + q(other), root);
  ASSERT_EQ(r.status, 0) << r.err;
  r = shell(bivo_cli() + " merge " + q(other) + " " + q(results), root);
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("another study"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(root / "other"));
}

TEST(LosoStudy, SeveralParametersAndLevelsAreCheckedWhenPlanned) {
  const TempDir temp("bivo_loso_plan_several");
  const fs::path& root = temp.path;
  const std::string flags = " --sequences /data/a /data/b --method robust --output " + q(root / "out") + " --study ";
  const auto plan = [&](const std::string& more) {
    return shell(bivo_cli() + " plan loso" + flags + q(root / "s.json") + " " + more, root);
  };
  const std::vector<std::pair<std::string, std::string>> refused = {
      {"--parameter trust --grid 1 2 --parameter robust_kappa", "2 --parameter (trust, robust_kappa) but 1 --grid"},
      {"--grid 1 --grid 2", "1 --parameter (trust) but 2 --grid"},
      {"--parameter trust --grid 1 --parameter trust --grid 2", "--parameter 'policy.trust' is given twice"},
      {"--parameter trust --grid 1 --parameter policy.trust --grid 2", "(as 'trust' and 'policy.trust')"},
      {"--parameter trust --grid --parameter robust_kappa --grid 1", "the --grid of 'trust' is empty"},
      {"--parameter trust --grid 1 x", "--grid value 'x' of 'trust' is not a number"},
      {"--grid 1 --finest-levels 0 4", "--finest-levels 4 is not a level of the pyramid (0..3 with --levels 4)"},
      {"--grid 1 --finest-levels 1 1", "--finest-levels lists 1 twice"},
      {"--grid 1 --finest-levels 0 2 --levels 2", "--finest-levels 2 is not a level"},
  };
  for (const auto& [more, message] : refused) {
    const Shell r = plan(more);
    EXPECT_EQ(r.status, 1) << more << ": " << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << more << ": " << r.err;
    EXPECT_FALSE(fs::exists(root / "s.json")) << more;
  }
  const Shell r =
      plan("--parameter trust --grid 100 1000 --parameter robust_kappa --grid 0.2 0.3 0.5 --finest-levels 0 1");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("loso study, 28 unit(s)"), std::string::npos) << r.err;  // 2 x 2 x (1 + 2 x 3)
  const nlohmann::json planned = nlohmann::json::parse(slurp(root / "s.json"));
  EXPECT_EQ(planned["loso"]["parameters"][1]["grid"], nlohmann::json({0.2, 0.3, 0.5}));
  EXPECT_EQ(planned["loso"]["finest_levels"], nlohmann::json({0, 1}));
}

TEST(LosoStudy, SeveralParametersAtPooledLevelsMergeToTheFilesOfOneProcess) {
  const TempDir temp("bivo_loso_study_several");
  const fs::path& root = temp.path;
  const std::vector<std::string> sequences = render_test_sequences(root / "sequences");
  std::string flags = "--sequences";
  for (const auto& s : sequences) flags += " " + q(s);
  flags +=
      " --method robust --parameter trust --grid 100 1e12 --parameter robust_kappa --grid 0.3 1 --max-frames 5"
      " --levels 4 --finest-levels 3 2 --output ";
  const Shell one = shell(bivo_cli() + " loso " + flags + q(root / "one"), root);
  ASSERT_EQ(one.status, 0) << one.err;
  const fs::path study = root / "study.json", results = root / "results";
  Shell r = shell(bivo_cli() + " plan loso " + flags + q(root / "merged") + " --study " + q(study), root);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("20 unit(s)"), std::string::npos) << r.err;  // 2 sequences x 2 levels x (1 + 4)
  for (const char* shard : {"0/2", "1/2"}) {
    r = shell(bivo_cli() + " work " + q(study) + " --shard " + shard + " --results " + q(results), root);
    ASSERT_EQ(r.status, 0) << r.err;
  }
  const Shell m = shell(bivo_cli() + " merge " + q(study) + " " + q(results), root);
  ASSERT_EQ(m.status, 0) << m.err;
  EXPECT_EQ(m.out, one.out);
  for (const char* exact : {"loso.md", "loso.csv", "pairs.csv", "config.json"}) {
    EXPECT_EQ(slurp(root / "one" / exact), slurp(root / "merged" / exact)) << exact;
  }
  EXPECT_EQ(without_column(slurp(root / "one" / "runs.csv"), "median_cpu_ms"),
            without_column(slurp(root / "merged" / "runs.csv"), "median_cpu_ms"));
  // A column per parameter and the finest level; a row per held-out sequence and level.
  const std::string md = slurp(root / "one" / "loso.md");
  EXPECT_EQ(md.find("failed"), std::string::npos) << md;
  EXPECT_NE(md.find("| held out | finest level | trust chosen | robust_kappa chosen | worst ratio on the others |"),
            std::string::npos)
      << md;
  for (const auto& s : sequences) {
    for (const char* level : {"3", "2"})
      EXPECT_NE(md.find("| " + fs::path(s).filename().string() + " | " + level + " |"), std::string::npos) << md;
  }
  const std::string csv = slurp(root / "one" / "loso.csv");
  EXPECT_EQ(csv.rfind("sequence,finest_level,chosen:trust,chosen:robust_kappa,train_worst,", 0), 0u) << csv;
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 5) << csv;  // a header and 2 x 2 rows
  const std::string runs = slurp(root / "one" / "runs.csv");
  EXPECT_EQ(runs.rfind("sequence,method,value:trust,value:robust_kappa,finest_level,ok,", 0), 0u) << runs;
  EXPECT_NE(runs.find(",single,,,3,1,"), std::string::npos) << runs;
  EXPECT_NE(runs.find(",robust,1e+12,0.3,2,1,"), std::string::npos) << runs;
  EXPECT_EQ(
      slurp(root / "one" / "pairs.csv").rfind("sequence,method,value:trust,value:robust_kappa,finest_level,pair,", 0),
      0u);
}

// loso had no --delta: sequences spanning fewer than two 1-s windows could not be studied.
TEST(LosoStudy, TheRpeWindowIsAFlag) {
  const TempDir temp("bivo_loso_delta");
  const fs::path& root = temp.path;
  std::string flags = "--sequences";
  for (const auto& s : render_test_sequences(root / "sequences")) flags += " " + q(s);
  flags += " --method robust --parameter trust --grid 1e12 --max-frames 4 --levels 4 --finest-level 3 --output ";
  // 4 frames at 2 Hz span 1.5 s: too short for two 1-s windows, named, nothing written.
  const Shell one_second = shell(bivo_cli() + " loso " + flags + q(root / "one"), root);
  EXPECT_EQ(one_second.status, 1);
  EXPECT_NE(one_second.err.find("windows of 1"), std::string::npos) << one_second.err;
  EXPECT_FALSE(fs::exists(root / "one"));
  const Shell half = shell(bivo_cli() + " loso " + flags + q(root / "half") + " --delta 0.5", root);
  ASSERT_EQ(half.status, 0) << half.err;
  EXPECT_NE(slurp(root / "half" / "loso.md").find("RPE trans [m per 0.5 s]"), std::string::npos);
}
