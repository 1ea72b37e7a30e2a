// Leave-one-sequence-out (experiments/loso.h): the value chosen for a held-out sequence is
// the one with the smallest worst ratio to the reference over the OTHER sequences (on a tie,
// the smaller geometric mean), checked on hand-made runs whose choice is known; bad inputs
// are refused before any run.
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "experiments/loso.h"
#include "solvers/error.h"
#include "test_support.h"

using namespace bivo::experiments;
using bivo::testing::error_of;

namespace {

LosoRun run(int sequence, const std::string& method, double trans, double rot, bool has_value = false,
            double value = 0.0) {
  LosoRun r;
  r.sequence = sequence;
  r.method = method;
  r.has_value = has_value;
  r.value = value;
  r.ok = true;
  r.sequence_name = "s" + std::to_string(sequence);
  r.rpe_trans = trans;
  r.rpe_rot = rot;
  return r;
}

}  // namespace

TEST(Loso, EachHeldOutSequenceGetsTheValueChosenWithoutIt) {
  LosoOptions o;
  o.sequences = {"a", "b", "c"};
  o.grid = {1.0, 2.0};
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
  EXPECT_EQ(r.rows[0].chosen, 2.0);
  EXPECT_DOUBLE_EQ(r.rows[0].train_worst, 0.95);
  EXPECT_EQ(r.rows[0].held_out->rpe_trans, 0.9);
  // Held out b: a and c; value 1 worst 1.5, value 2 worst 0.9 -> 2.
  EXPECT_EQ(r.rows[1].chosen, 2.0);
  // Held out c: a and b; value 1 worst 0.8, value 2 worst 0.95 -> 1, reported on c at 1.
  EXPECT_EQ(r.rows[2].chosen, 1.0);
  EXPECT_DOUBLE_EQ(r.rows[2].train_worst, 0.8);
  EXPECT_EQ(r.rows[2].held_out->rpe_rot, 1.5);
}

TEST(Loso, ATieOnTheWorstSequenceGoesToTheSmallerGeometricMean) {
  LosoOptions o;
  o.sequences = {"a", "b", "c"};
  o.grid = {1.0, 2.0, 3.0};
  std::vector<LosoRun> runs;
  for (int s = 0; s < 3; ++s) runs.push_back(run(s, "single", 1.0, 1.0));
  // Sequence a is 0.9x at every value (the value does not reach it); b and c tell them apart.
  for (double v : o.grid) runs.push_back(run(0, "robust", 0.9, 0.8, true, v));
  runs.push_back(run(1, "robust", 0.8, 0.8, true, 1.0));
  runs.push_back(run(1, "robust", 0.4, 0.5, true, 2.0));
  runs.push_back(run(1, "robust", 0.4, 0.5, true, 3.0));
  runs.push_back(run(2, "robust", 0.7, 0.6, true, 1.0));
  runs.push_back(run(2, "robust", 0.5, 0.3, true, 2.0));
  runs.push_back(run(2, "robust", 0.3, 0.2, true, 3.0));
  const LosoResult r = assemble_loso(o, runs);
  ASSERT_EQ(r.rows.size(), 3u);
  // Held out b: a ties at 0.9; c's 0.7 / 0.5 / 0.3 -> 3.
  EXPECT_EQ(r.rows[1].chosen, 3.0);
  EXPECT_DOUBLE_EQ(r.rows[1].train_worst, 0.9);
  // Held out c: a ties at 0.9, b 0.8 / 0.5 / 0.5: 2 and 3 tie again -> the first, 2.
  EXPECT_EQ(r.rows[2].chosen, 2.0);
  // Held out a: worst 0.8 / 0.5 / 0.5 -> 2 and 3 tie, geometric mean sqrt(0.5 * 0.5) against
  // sqrt(0.5 * 0.3) -> 3.
  EXPECT_EQ(r.rows[0].chosen, 3.0);
  EXPECT_DOUBLE_EQ(r.rows[0].train_worst, 0.5);
}

TEST(Loso, ACostBudgetLeavesOnlyTheValuesWithinItOnTheOthers) {
  LosoOptions o;
  o.sequences = {"a", "b", "c"};
  o.grid = {1.0, 2.0, 3.0};
  o.methods = {"weighted"};
  o.cost_budget = 1.3;
  std::vector<LosoRun> runs;
  const auto timed = [](LosoRun r, double cpu_ms) {
    r.median_cpu_ms = cpu_ms;
    return r;
  };
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
  // Held out a: value 1 costs (11 + 11) / (10 + 10) = 1.1x weighted on b and c, within.
  EXPECT_EQ(r.rows[0].chosen, 1.0);
  EXPECT_DOUBLE_EQ(r.rows[0].train_cost, 1.1);
  EXPECT_DOUBLE_EQ(r.rows[0].train_worst, 0.5);
  // Held out b (or c): a is on the others, value 1 costs (20 + 11) / 20 = 1.55x, beyond the
  // budget; the most accurate value within it is 2 (1.2x).
  for (int h : {1, 2}) {
    EXPECT_EQ(r.rows[h].chosen, 2.0) << h;
    EXPECT_DOUBLE_EQ(r.rows[h].train_cost, 1.2) << h;
    EXPECT_DOUBLE_EQ(r.rows[h].train_worst, 0.6) << h;
  }
  // No budget: accuracy alone, value 1 in every fold.
  o.cost_budget = 0.0;
  for (const LosoRow& row : assemble_loso(o, runs).rows) EXPECT_EQ(row.chosen, 1.0);
  // A budget nothing keeps within: the cheapest value (3, 1.08x on every pair of sequences).
  o.cost_budget = 1.05;
  r = assemble_loso(o, runs);
  for (const LosoRow& row : r.rows) {
    EXPECT_EQ(row.chosen, 3.0);
    EXPECT_DOUBLE_EQ(row.train_cost, 1.08);
  }
  // In units of the reference, budget 1.4x single: without a, value 1 costs 1.375x; with a,
  // only 3 keeps within (1.35x; 1 costs 1.94x, 2 1.5x).
  o.cost_method = "single";
  o.cost_budget = 1.4;
  r = assemble_loso(o, runs);
  EXPECT_EQ(r.rows[0].chosen, 1.0);
  EXPECT_EQ(r.rows[1].chosen, 3.0);
}

TEST(Loso, RefusesACostBudgetItCannotMeasure) {
  LosoOptions o;
  o.sequences = {"a", "b"};
  o.grid = {1.0};
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
  o.grid = {1.0};
  EXPECT_THROW(loso_units(o), bivo::Error);
  o.sequences = {"a", "b"};
  o.grid = {};
  EXPECT_THROW(loso_units(o), bivo::Error);
  o.grid = {1.0};
  o.parameter = "no_such_parameter";
  EXPECT_THROW(loso_units(o), bivo::Error);
  o.parameter = "trust";
  EXPECT_EQ(loso_units(o).size(), 4u);  // per sequence: single, one grid value
  // Any numeric tracker option, by its JSON key, checked as a flag would be.
  o.parameter = "problem.depth_noise_exponent";
  o.grid = {0.0, 2.0};
  EXPECT_EQ(loso_units(o).size(), 6u);
  for (double bad : {0.5, 4.0}) {
    o.grid = {0.0, bad};
    EXPECT_THROW(loso_units(o), bivo::Error) << bad;
  }
  o.parameter = "method";  // text, not a number
  o.grid = {1.0};
  EXPECT_THROW(loso_units(o), bivo::Error);
  o.parameter = "trust";
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
