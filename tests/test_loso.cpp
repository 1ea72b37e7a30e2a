// Leave-one-sequence-out (experiments/loso.h): the value chosen for a held-out sequence is,
// over the OTHER sequences, the smallest geometric mean of those within the acceptable worst
// ratio to the reference, else the smallest worst ratio, checked on hand-made runs whose
// choice is known; several
// parameters are chosen over the product of their grids, pooled finest levels all at once;
// bad inputs are refused before any run.
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "experiments/loso.h"
#include "solvers/error.h"
#include "test_support.h"

using namespace bivo::experiments;
using bivo::testing::error_of;
using V = std::vector<double>;

namespace {

LosoRun run(int sequence, const std::string& method, double trans, double rot, bool has_value = false,
            double value = 0.0, int finest_level = -1) {
  LosoRun r;
  r.sequence = sequence;
  r.method = method;
  if (has_value) r.values = {value};
  r.finest_level = finest_level;
  r.ok = true;
  r.sequence_name = "s" + std::to_string(sequence);
  r.rpe_trans = trans;
  r.rpe_rot = rot;
  return r;
}

// A run with its median CPU per pair.
LosoRun timed(LosoRun r, double cpu_ms) {
  r.median_cpu_ms = cpu_ms;
  return r;
}

// A study of robust over `grid` within 1.3x weighted's CPU per pair.
LosoOptions budgeted(std::vector<std::string> sequences, std::vector<double> grid) {
  LosoOptions o;
  o.sequences = std::move(sequences);
  o.parameters[0].grid = std::move(grid);
  o.methods = {"weighted"};
  o.cost_budget = 1.3;
  return o;
}

}  // namespace

TEST(Loso, EachHeldOutSequenceGetsTheValueChosenWithoutIt) {
  LosoOptions o;
  o.sequences = {"a", "b", "c"};
  o.parameters[0].grid = {1.0, 2.0};
  std::vector<LosoRun> runs;
  for (int s = 0; s < 3; ++s) runs.push_back(run(s, "single", 1.0, 1.0));
  // Value 1 is best on a and b, value 2 on c; each sequence's worst ratio decides.
  runs.push_back(run(0, "robust", 0.5, 0.6, true, 1.0));
  runs.push_back(run(0, "robust", 0.9, 0.9, true, 2.0));
  runs.push_back(run(1, "robust", 0.7, 0.8, true, 1.0));
  runs.push_back(run(1, "robust", 0.95, 0.9, true, 2.0));
  runs.push_back(run(2, "robust", 1.0, 1.5, true, 1.0));  // rotation decides: 1.5x
  runs.push_back(run(2, "robust", 0.8, 0.9, true, 2.0));
  const LosoResult r = assemble_loso(o, runs);
  ASSERT_EQ(r.rows.size(), 3u);
  // Held out a: b and c decide; value 1 worst 1.5 (c), value 2 worst 0.95 (b) -> 2.
  EXPECT_EQ(r.rows[0].chosen, V{2.0});
  EXPECT_DOUBLE_EQ(r.rows[0].train_worst, 0.95);
  EXPECT_EQ(r.rows[0].held_out->rpe_trans, 0.9);
  // Held out b: a and c; value 1 worst 1.5, value 2 worst 0.9 -> 2.
  EXPECT_EQ(r.rows[1].chosen, V{2.0});
  // Held out c: a and b; value 1 worst 0.8, value 2 worst 0.95 -> 1, reported on c at 1.
  EXPECT_EQ(r.rows[2].chosen, V{1.0});
  EXPECT_DOUBLE_EQ(r.rows[2].train_worst, 0.8);
  EXPECT_EQ(r.rows[2].held_out->rpe_rot, 1.5);
}

TEST(Loso, ATieOnTheWorstSequenceGoesToTheSmallerGeometricMean) {
  LosoOptions o;
  o.acceptable_ratio = 0.0;  // the worst ratio decides, the geometric mean only on a tie
  o.sequences = {"a", "b", "c"};
  o.parameters[0].grid = {1.0, 2.0, 3.0};
  std::vector<LosoRun> runs;
  for (int s = 0; s < 3; ++s) runs.push_back(run(s, "single", 1.0, 1.0));
  // Sequence a is 0.9x at every value (the value does not reach it); b and c tell them apart.
  for (double v : o.parameters[0].grid) runs.push_back(run(0, "robust", 0.9, 0.8, true, v));
  runs.push_back(run(1, "robust", 0.8, 0.8, true, 1.0));
  runs.push_back(run(1, "robust", 0.4, 0.5, true, 2.0));
  runs.push_back(run(1, "robust", 0.4, 0.5, true, 3.0));
  runs.push_back(run(2, "robust", 0.7, 0.6, true, 1.0));
  runs.push_back(run(2, "robust", 0.5, 0.3, true, 2.0));
  runs.push_back(run(2, "robust", 0.3, 0.2, true, 3.0));
  const LosoResult r = assemble_loso(o, runs);
  ASSERT_EQ(r.rows.size(), 3u);
  // Held out b: a ties at 0.9; c's 0.7 / 0.5 / 0.3 -> 3.
  EXPECT_EQ(r.rows[1].chosen, V{3.0});
  EXPECT_DOUBLE_EQ(r.rows[1].train_worst, 0.9);
  // Held out c: a ties at 0.9, b 0.8 / 0.5 / 0.5: 2 and 3 tie again -> the first, 2.
  EXPECT_EQ(r.rows[2].chosen, V{2.0});
  // Held out a: worst 0.8 / 0.5 / 0.5 -> 2 and 3 tie, geometric mean sqrt(0.5 * 0.5) against
  // sqrt(0.5 * 0.3) -> 3.
  EXPECT_EQ(r.rows[0].chosen, V{3.0});
  EXPECT_DOUBLE_EQ(r.rows[0].train_worst, 0.5);
}

// Among the settings within the acceptable ratio on the other sequences, the smallest geometric
// mean wins, even against one whose worst ratio is smaller (a value at which the method does
// nothing); a setting beyond it is never chosen for its mean; when none is within, the
// smallest worst ratio decides.
TEST(Loso, AnAcceptableSettingIsChosenByItsGeometricMean) {
  LosoOptions o;
  o.sequences = {"a", "b", "c", "d"};
  o.parameters[0].grid = {1.0, 2.0, 3.0};
  std::vector<LosoRun> runs;
  for (int s = 0; s < 4; ++s) {
    runs.push_back(run(s, "single", 1.0, 1.0));
    runs.push_back(run(s, "robust", 1.0, 1.0, true, 1.0));                  // inert: single on every sequence
    runs.push_back(run(s, "robust", 0.5, s == 0 ? 1.02 : 0.4, true, 2.0));  // 1.02x on a (rotation)
    runs.push_back(run(s, "robust", 0.2, s == 1 ? 1.2 : 0.1, true, 3.0));   // 1.2x on b
  }
  LosoResult r = assemble_loso(o, runs);
  ASSERT_EQ(r.rows.size(), 4u);
  // Held out d (a, b, c): 1 worst 1.0, mean 1; 2 worst 1.02, mean (1.02 * 0.5 * 0.5)^(1/3);
  // 3 worst 1.2, beyond 1.05 -> 2.
  EXPECT_EQ(r.rows[3].chosen, V{2.0});
  EXPECT_DOUBLE_EQ(r.rows[3].train_worst, 1.02);
  EXPECT_NEAR(r.rows[3].train_mean, std::cbrt(1.02 * 0.5 * 0.5), 1e-12);
  // Held out b: 3 is within on a, c, d (0.2x) and has the smallest mean -> 3.
  EXPECT_EQ(r.rows[1].chosen, V{3.0});
  EXPECT_NEAR(r.rows[1].train_mean, 0.2, 1e-12);
  // Held out a: 2 is 0.5x everywhere else, 3 is 1.2x on b -> 2.
  EXPECT_EQ(r.rows[0].chosen, V{2.0});
  // The smallest worst ratio alone (0) prefers doing nothing wherever 2's 1.02x counts.
  o.acceptable_ratio = 0.0;
  r = assemble_loso(o, runs);
  EXPECT_EQ(r.rows[3].chosen, V{1.0});
  EXPECT_EQ(r.rows[0].chosen, V{2.0});  // without a, 2 is 0.5x at worst
  // Within 1.01: 2 is out wherever a counts, 1 is in.
  o.acceptable_ratio = 1.01;
  EXPECT_EQ(assemble_loso(o, runs).rows[3].chosen, V{1.0});
  // None within 0.9 where a and b both count: the smallest worst ratio, 1 (1.0 against 1.02
  // and 1.2), not the smallest mean (3).
  o.acceptable_ratio = 0.9;
  EXPECT_EQ(assemble_loso(o, runs).rows[2].chosen, V{1.0});
  // Bad values are refused before any run.
  o.acceptable_ratio = -1.0;
  EXPECT_NE(error_of([&] { loso_units(o); }).find("acceptable ratio must be finite and >= 0"), std::string::npos);
}

TEST(Loso, ACostBudgetLeavesOnlyTheValuesWithinItOnTheOthers) {
  LosoOptions o = budgeted({"a", "b", "c"}, {1.0, 2.0, 3.0});
  std::vector<LosoRun> runs;
  for (int s = 0; s < 3; ++s) {
    runs.push_back(timed(run(s, "single", 1.0, 1.0), 8.0));
    runs.push_back(timed(run(s, "weighted", 1.0, 1.0), 10.0));
    // Value 1 is the most accurate everywhere, 2 next, 3 the least; 3 is the cheapest.
    runs.push_back(timed(run(s, "robust", 0.5, 0.5, true, 1.0), s == 0 ? 20.0 : 11.0));
    runs.push_back(timed(run(s, "robust", 0.6, 0.6, true, 2.0), 12.0));
    runs.push_back(timed(run(s, "robust", 0.7, 0.7, true, 3.0), 10.8));
  }
  LosoResult r = assemble_loso(o, runs);
  ASSERT_EQ(r.rows.size(), 3u);
  // Held out a: value 1 costs 11 / 10 = 1.1x weighted on b and on c, within.
  EXPECT_EQ(r.rows[0].chosen, V{1.0});
  EXPECT_NEAR(r.rows[0].train_cost, 1.1, 1e-12);
  EXPECT_DOUBLE_EQ(r.rows[0].train_worst, 0.5);
  // Held out b (or c): a is on the others, value 1 costs sqrt(20 / 10 * 11 / 10) = 1.48x,
  // beyond the budget; the most accurate value within it is 2 (1.2x).
  for (int h : {1, 2}) {
    EXPECT_EQ(r.rows[h].chosen, V{2.0}) << h;
    EXPECT_NEAR(r.rows[h].train_cost, 1.2, 1e-12) << h;
    EXPECT_DOUBLE_EQ(r.rows[h].train_worst, 0.6) << h;
  }
  // No budget: accuracy alone, value 1 in every fold.
  o.cost_budget = 0.0;
  for (const LosoRow& row : assemble_loso(o, runs).rows) EXPECT_EQ(row.chosen, V{1.0});
  // A budget nothing keeps within: the cheapest value (3, 1.08x on every pair of sequences).
  o.cost_budget = 1.05;
  r = assemble_loso(o, runs);
  for (const LosoRow& row : r.rows) {
    EXPECT_EQ(row.chosen, V{3.0});
    EXPECT_NEAR(row.train_cost, 1.08, 1e-12);
  }
  // In units of the reference, budget 1.4x single: without a, value 1 costs 1.375x; with a,
  // only 3 keeps within (1.35x; 1 costs sqrt(2.5 * 1.375) = 1.85x, 2 1.5x).
  o.cost_method = "single";
  o.cost_budget = 1.4;
  r = assemble_loso(o, runs);
  EXPECT_EQ(r.rows[0].chosen, V{1.0});
  EXPECT_EQ(r.rows[1].chosen, V{3.0});
}

// The budget is per sequence: a sequence slow for both methods (a cost they share, such as a
// rolling-shutter correction) must not dilute a setting that doubles the CPU elsewhere.
TEST(Loso, ACostBudgetIsTheGeometricMeanOfThePerSequenceRatios) {
  LosoOptions o = budgeted({"a", "b", "c", "d"}, {1.0, 2.0});
  std::vector<LosoRun> runs;
  for (int s = 0; s < 4; ++s) {
    const double shared = s == 0 ? 100.0 : 0.0;  // a: both pay 100 ms more per pair
    runs.push_back(timed(run(s, "single", 1.0, 1.0), 8.0));
    runs.push_back(timed(run(s, "weighted", 1.0, 1.0), 10.0 + shared));
    runs.push_back(timed(run(s, "robust", 0.5, 0.5, true, 1.0), 20.0 + shared));  // 2x weighted's own
    runs.push_back(timed(run(s, "robust", 0.6, 0.6, true, 2.0), 12.0 + shared));
  }
  const LosoResult r = assemble_loso(o, runs);
  ASSERT_EQ(r.rows.size(), 4u);
  // Held out d: value 1 costs 120 / 110 on a, 2x on b and c: (1.09 * 2 * 2)^(1/3) = 1.63x,
  // beyond 1.3 (the ratio of the sums, 160 / 130 = 1.23x, would keep it).
  EXPECT_EQ(r.rows[3].chosen, V{2.0});
  EXPECT_NEAR(r.rows[3].train_cost, std::cbrt(112.0 / 110.0 * 1.2 * 1.2), 1e-12);
  // Held out a: 2x on each of b, c, d; value 2 (1.2x) in every fold.
  for (const LosoRow& row : r.rows) EXPECT_EQ(row.chosen, V{2.0}) << row.sequence;
}

TEST(Loso, RefusesACostBudgetItCannotMeasure) {
  LosoOptions o;
  o.sequences = {"a", "b"};
  o.parameters[0].grid = {1.0};
  o.cost_budget = 1.3;  // in units of weighted, which does not run
  EXPECT_NE(error_of([&] { loso_units(o); }).find("'weighted', which is neither the reference nor among the methods"),
            std::string::npos);
  o.methods = {"weighted"};
  EXPECT_EQ(loso_units(o).size(), 6u);
  for (double bad : {-1.0, std::numeric_limits<double>::infinity(), std::nan("")}) {
    o.cost_budget = bad;
    EXPECT_NE(error_of([&] { loso_units(o); }).find("cost budget must be finite and >= 0"), std::string::npos) << bad;
  }
  o.cost_budget = 1.3;
  std::vector<LosoRun> runs;
  for (int s = 0; s < 2; ++s) {
    runs.push_back(run(s, "single", 1.0, 1.0));
    runs.push_back(run(s, "robust", 1.0, 1.0, true, 1.0));
    runs.push_back(run(s, "weighted", 1.0, 1.0));
  }
  runs[5].ok = false;
  runs[5].error = "unreadable frame";
  EXPECT_NE(error_of([&] { assemble_loso(o, runs); }).find("the cost method's run (weighted) on 'b' failed"),
            std::string::npos);
}

TEST(Loso, RefusesWhatCannotBeHeldOut) {
  LosoOptions o;
  o.sequences = {"only"};
  o.parameters[0].grid = {1.0};
  EXPECT_THROW(loso_units(o), bivo::Error);
  o.sequences = {"a", "b"};
  o.parameters[0].grid = {};
  EXPECT_THROW(loso_units(o), bivo::Error);
  o.parameters[0].grid = {1.0};
  o.parameters[0].name = "no_such_parameter";
  EXPECT_THROW(loso_units(o), bivo::Error);
  o.parameters[0].name = "trust";
  EXPECT_EQ(loso_units(o).size(), 4u);  // per sequence: single, one grid value
  // Any numeric tracker option, by its JSON key, checked as a flag would be.
  o.parameters[0].name = "problem.depth_noise_exponent";
  o.parameters[0].grid = {0.0, 2.0};
  EXPECT_EQ(loso_units(o).size(), 6u);
  for (double bad : {0.5, 4.0}) {
    o.parameters[0].grid = {0.0, bad};
    EXPECT_THROW(loso_units(o), bivo::Error) << bad;
  }
  o.parameters[0].name = "method";  // text, not a number
  o.parameters[0].grid = {1.0};
  EXPECT_THROW(loso_units(o), bivo::Error);
  o.parameters[0].name = "trust";
  // A failed reference leaves the ratios undefined.
  std::vector<LosoRun> runs = {run(0, "single", 1.0, 1.0), run(1, "single", 1.0, 1.0),
                               run(0, "robust", 1.0, 1.0, true, 1.0), run(1, "robust", 1.0, 1.0, true, 1.0)};
  runs[1].ok = false;
  runs[1].error = "no groundtruth";
  EXPECT_THROW(assemble_loso(o, runs), bivo::Error);
}

TEST(Loso, TheParameterReachesItsTrackerField) {
  bivo::odometry::TrackerOptions t;
  set_loso_parameter(t, "problem.depth_noise_exponent", 2.0);
  EXPECT_EQ(t.problem.depth_noise_exponent, 2);
  set_loso_parameter(t, "trust", 42.0);
  EXPECT_EQ(t.policy.trust, 42.0);
  set_loso_parameter(t, "policy.kappa", 0.25);
  EXPECT_EQ(t.policy.kappa, 0.25);
  EXPECT_THROW(set_loso_parameter(t, "policy.kappa", -1.0), bivo::Error);  // outside [0, inf]
}

TEST(Loso, SeveralParametersAreChosenTogetherOverTheProductOfTheirGrids) {
  LosoOptions o;
  o.sequences = {"a", "b", "c"};
  o.parameters = {{"trust", {1.0, 2.0}}, {"kappa", {10.0, 20.0}}};
  const std::vector<V> settings = {{1, 10}, {1, 20}, {2, 10}, {2, 20}};
  EXPECT_EQ(loso_settings(o), settings);  // the first parameter's values vary slowest
  const std::vector<LosoRun> units = loso_units(o);
  EXPECT_EQ(units.size(), 15u);  // per sequence: single, 4 settings
  for (std::size_t k = 0; k < 4 && k + 1 < units.size(); ++k) EXPECT_EQ(units[k + 1].values, settings[k]) << k;
  // The same ratio in translation and rotation: (1, 10) 0.8, (1, 20) 0.9, (2, 10) 0.95,
  // (2, 20) 0.5, but c is lost at (2, 20). Only the pair (2, 20) is good: chosen one
  // parameter at a time (the other at its first value) gives (1, 10), by each parameter's
  // worst over the other's grid (1, 20).
  std::vector<LosoRun> runs;
  for (int s = 0; s < 3; ++s) {
    runs.push_back(run(s, "single", 1.0, 1.0));
    const V ratios = {0.8, 0.9, 0.95, s == 2 ? 2.0 : 0.5};
    for (std::size_t k = 0; k < 4; ++k) {
      LosoRun r = run(s, "robust", ratios[k], ratios[k]);
      r.values = settings[k];
      runs.push_back(r);
    }
  }
  const LosoResult r = assemble_loso(o, runs);
  ASSERT_EQ(r.rows.size(), 3u);
  // Held out a or b: c is among the others, lost at (2, 20) -> (1, 10).
  for (int h : {0, 1}) {
    EXPECT_EQ(r.rows[h].chosen, (V{1, 10})) << h;
    EXPECT_DOUBLE_EQ(r.rows[h].train_worst, 0.8) << h;
  }
  // Held out c: (2, 20) is 0.5x on a and b; reported on c at (2, 20), where it is lost.
  EXPECT_EQ(r.rows[2].chosen, (V{2, 20}));
  EXPECT_DOUBLE_EQ(r.rows[2].train_worst, 0.5);
  ASSERT_TRUE(r.rows[2].held_out);
  EXPECT_EQ(r.rows[2].held_out->values, (V{2, 20}));
  EXPECT_EQ(r.rows[2].held_out->rpe_trans, 2.0);
}

// Runs at finest levels 0 and 1: single's RPE is 1 at level 0 and 2 at level 1; the method's
// ratio at each level (to single at that level) per value.
std::vector<LosoRun> pooled_runs(const std::vector<std::vector<V>>& ratios_per_sequence, const V& grid) {
  std::vector<LosoRun> runs;
  for (int s = 0; s < int(ratios_per_sequence.size()); ++s) {
    for (int level : {0, 1}) {
      const double single = level == 0 ? 1.0 : 2.0;
      runs.push_back(run(s, "single", single, single, false, 0.0, level));
      for (std::size_t k = 0; k < grid.size(); ++k) {
        const double ratio = ratios_per_sequence[s][k][level];
        runs.push_back(run(s, "robust", ratio * single, ratio * single, true, grid[k], level));
      }
    }
  }
  return runs;
}

TEST(Loso, PooledFinestLevelsChooseOnTheWorstRatioOverEveryLevel) {
  LosoOptions o;
  o.sequences = {"a", "b", "c"};
  o.parameters[0].grid = {1.0, 2.0, 3.0};
  o.finest_levels = {0, 1};
  const std::vector<LosoRun> units = loso_units(o);
  ASSERT_EQ(units.size(), 24u);  // per sequence and level: single, 3 values
  EXPECT_EQ(units[0].finest_level, 0);
  EXPECT_EQ(units[4].finest_level, 1);
  EXPECT_EQ(units[4].method, "single");
  // Ratios (level 0, level 1) on every sequence: 1 is best at level 0 alone, 2 at level 1
  // alone, 3 at both at once. c has a second-best 3 at level 1, so its fold alone differs.
  const std::vector<V> everywhere = {{0.5, 1.2}, {1.1, 0.5}, {0.9, 0.9}};
  std::vector<LosoRun> runs = pooled_runs({everywhere, everywhere, {{0.5, 1.2}, {1.1, 0.5}, {0.9, 0.95}}}, {1, 2, 3});
  LosoResult r = assemble_loso(o, runs);
  ASSERT_EQ(r.rows.size(), 6u);  // per held-out sequence, a row per level
  for (int k = 0; k < 6; ++k) {
    EXPECT_EQ(r.rows[k].sequence, "s" + std::to_string(k / 2)) << k;
    EXPECT_EQ(r.rows[k].finest_level, k % 2) << k;
    EXPECT_EQ(r.rows[k].chosen, V{3.0}) << k;
    ASSERT_TRUE(r.rows[k].held_out) << k;
    EXPECT_EQ(r.rows[k].held_out->finest_level, k % 2) << k;
    EXPECT_EQ(r.rows[k].held_out->values, V{3.0}) << k;
    EXPECT_EQ(r.rows[k].reference->finest_level, k % 2) << k;  // each level's ratio to its own single
  }
  EXPECT_DOUBLE_EQ(r.rows[0].train_worst, 0.95);  // held out a: c's 0.95 at level 1
  EXPECT_DOUBLE_EQ(r.rows[4].train_worst, 0.9);   // held out c
  // One level alone chooses otherwise: the pooled choice is not either level's.
  for (int level : {0, 1}) {
    LosoOptions one = o;
    one.finest_levels = {level};
    std::vector<LosoRun> at_level;
    for (const LosoRun& run : runs) {
      if (run.finest_level == level) at_level.push_back(run);
    }
    for (const LosoRow& row : assemble_loso(one, at_level).rows) EXPECT_EQ(row.chosen, V{level == 0 ? 1.0 : 2.0});
  }
  // A tie on the worst ratio over both levels goes to the geometric mean over both.
  runs = pooled_runs({{{0.9, 0.5}, {0.9, 0.6}}, {{0.9, 0.5}, {0.9, 0.6}}, {{0.9, 0.75}, {0.9, 0.6}}}, {1, 2});
  o.parameters[0].grid = {1.0, 2.0};
  r = assemble_loso(o, runs);
  EXPECT_EQ(r.rows[4].chosen, V{1.0});  // held out c: 0.5 and 0.5 at level 1 against 0.6 and 0.6
  EXPECT_EQ(r.rows[0].chosen, V{2.0});  // held out a: 0.5 * 0.75 against 0.6 * 0.6
  // A reference missing at one level leaves that level's ratios undefined.
  runs.erase(runs.begin() + 3);  // a's single at level 1
  EXPECT_NE(error_of([&] { assemble_loso(o, runs); }).find("the reference run (single) on 'a' at finest level 1"),
            std::string::npos);
}

TEST(Loso, WithPooledLevelsACostBudgetHoldsAtEveryLevel) {
  LosoOptions o;
  o.sequences = {"a", "b", "c"};
  o.parameters[0].grid = {1.0, 2.0};
  o.methods = {"weighted"};
  o.finest_levels = {0, 1};
  o.cost_budget = 1.3;
  // Value 1 is the more accurate at both levels and costs 1.0x weighted at level 0 but 1.5x at
  // level 1 (1.25x over both levels' CPU together); value 2 costs 1.1x at each.
  std::vector<LosoRun> runs;
  for (int s = 0; s < 3; ++s) {
    for (int level : {0, 1}) {
      const auto timed = [](LosoRun r, double cpu_ms) {
        r.median_cpu_ms = cpu_ms;
        return r;
      };
      runs.push_back(timed(run(s, "single", 1.0, 1.0, false, 0.0, level), 8.0));
      runs.push_back(timed(run(s, "robust", 0.5, 0.5, true, 1.0, level), level == 0 ? 10.0 : 15.0));
      runs.push_back(timed(run(s, "robust", 0.6, 0.6, true, 2.0, level), 11.0));
      runs.push_back(timed(run(s, "weighted", 1.0, 1.0, false, 0.0, level), 10.0));
    }
  }
  LosoResult r = assemble_loso(o, runs);
  ASSERT_EQ(r.rows.size(), 6u);
  for (const LosoRow& row : r.rows) {
    EXPECT_EQ(row.chosen, V{2.0});
    EXPECT_DOUBLE_EQ(row.train_cost, 1.1);  // at the row's level
    EXPECT_DOUBLE_EQ(row.train_worst, 0.6);
    ASSERT_EQ(row.others.size(), 1u);
    EXPECT_EQ(row.others[0]->finest_level, row.finest_level);
  }
  // Level 0 alone: value 1 keeps within the budget and is chosen.
  o.finest_levels = {0};
  std::vector<LosoRun> level0;
  for (const LosoRun& run : runs) {
    if (run.finest_level == 0) level0.push_back(run);
  }
  for (const LosoRow& row : assemble_loso(o, level0).rows) EXPECT_EQ(row.chosen, V{1.0});
  // Nothing within 1.05x at every level: the cheapest at its most expensive level, 2 (1.1x
  // against 1.5x), though 1 is the cheaper at level 0.
  o.finest_levels = {0, 1};
  o.cost_budget = 1.05;
  r = assemble_loso(o, runs);
  EXPECT_EQ(r.rows[0].chosen, V{2.0});
  EXPECT_DOUBLE_EQ(r.rows[0].train_cost, 1.1);
}

TEST(Loso, RefusesParametersAndLevelsItCannotHoldOut) {
  LosoOptions o;
  o.sequences = {"a", "b"};
  o.parameters = {};
  EXPECT_NE(error_of([&] { loso_units(o); }).find("no --parameter"), std::string::npos);
  o.parameters = {{"trust", {1.0}}, {"robust_kappa", {}}};
  EXPECT_NE(error_of([&] { loso_units(o); }).find("the --grid of 'robust_kappa' is empty"), std::string::npos);
  o.parameters = {{"trust", {1.0}}, {"trust", {2.0}}};
  EXPECT_NE(error_of([&] { loso_units(o); }).find("--parameter 'policy.trust' is given twice"), std::string::npos);
  o.parameters = {{"trust", {1.0}}, {"policy.trust", {2.0}}};  // one option under two names
  EXPECT_NE(error_of([&] { loso_units(o); }).find("given twice (as 'trust' and 'policy.trust')"), std::string::npos);
  o.parameters = {{"trust", {1.0}}, {"problem.depth_noise_exponent", {2.0, 4.0}}};  // p is in [0, 3]
  EXPECT_NE(error_of([&] { loso_units(o); }).find("depth_noise_exponent"), std::string::npos);
  o.parameters = {{"trust", {1.0, 2.0}}, {"problem.depth_noise_exponent", {2.0, 3.0}}};
  EXPECT_EQ(loso_units(o).size(), 10u);
  o.tracker.levels = 3;
  for (int bad : {-1, 3}) {
    o.finest_levels = {0, bad};
    EXPECT_NE(error_of([&] {
                loso_units(o);
              }).find("--finest-levels " + std::to_string(bad) + " is not a level of the pyramid (0..2"),
              std::string::npos)
        << bad;
  }
  o.finest_levels = {1, 2, 1};
  EXPECT_NE(error_of([&] { loso_units(o); }).find("--finest-levels lists 1 twice"), std::string::npos);
  o.finest_levels = {2, 0};
  EXPECT_EQ(loso_units(o).size(), 20u);
  o.parameters.push_back({"finest_level", {1.0}});  // the runs' finest level, twice over
  EXPECT_NE(error_of([&] { loso_units(o); }).find("--parameter finest_level and --finest-levels"), std::string::npos);
  o.parameters.pop_back();
  EXPECT_EQ(loso_units(o)[5].finest_level, 0);  // in the order given
}
