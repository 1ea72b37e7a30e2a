// Leave-one-sequence-out as a study (experiments/study/study.h, kind "loso"): its file reads
// back bit for bit and its hash covers what the runs compute.
#include <algorithm>
#include <cmath>

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
  o.parameter = "trust";
  o.grid = {300, 0.1 + 0.2, 1e12};  // 0.1 + 0.2: not a short decimal, must survive bit for bit
  o.reference = "single";
  o.methods = {"weighted", "joint"};
  o.first_frame = 2;
  o.max_frames = 40;
  s.loso = o;
  return s;
}

}  // namespace

TEST(LosoStudy, FileRoundTripsAndTheHashCoversTheLosoPart) {
  const Study s = loso_study_by_hand();
  check_study(s);
  const nlohmann::json j = study_to_json(s);
  const Study back = study_from_json(nlohmann::json::parse(j.dump()), "s.json");
  EXPECT_EQ(study_to_json(back), j);
  ASSERT_TRUE(back.loso);
  EXPECT_EQ(back.loso->grid[1], 0.1 + 0.2);
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
  EXPECT_NE(hash_with([](Study& t) { t.loso->parameter = "kappa"; }), h);
  EXPECT_NE(hash_with([](Study& t) { t.loso->grid[0] = 301; }), h);
  EXPECT_NE(hash_with([](Study& t) { t.loso->reference = "weighted"; }), h);
  EXPECT_NE(hash_with([](Study& t) { t.loso->methods.pop_back(); }), h);
  EXPECT_NE(hash_with([](Study& t) { t.loso->first_frame = 3; }), h);
  EXPECT_NE(hash_with([](Study& t) { t.loso->max_frames = 41; }), h);
  EXPECT_NE(hash_with([](Study& t) { t.tracker.levels = 4; }), h);

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
  bad = j;
  bad["loso"]["methods"][1] = "single";  // the reference twice: two units of one name
  EXPECT_NE(error_of([&] { study_units(study_from_json(bad, "s.json")); }).find("two units named"), std::string::npos);
}

TEST(LosoStudy, ARunReadsBackBitForBit) {
  LosoRun r;
  r.sequence = 1;
  r.method = "robust";
  r.has_value = true;
  r.value = 0.1 + 0.2;
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
  EXPECT_TRUE(back.has_value);
  EXPECT_EQ(back.value, r.value);
  EXPECT_TRUE(back.ok);
  EXPECT_EQ(back.sequence_name, "teddy");
  EXPECT_EQ(back.rpe_trans, r.rpe_trans);
  EXPECT_EQ(back.rpe_rot, r.rpe_rot);
  EXPECT_EQ(back.median_cpu_ms, 12.5);
  EXPECT_EQ(back.pair_trans, r.pair_trans);
  EXPECT_EQ(back.pair_rot, r.pair_rot);
}
