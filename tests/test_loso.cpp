// Leave-one-sequence-out (experiments/loso.h): the value chosen for a held-out sequence is
// the one with the smallest worst ratio to the reference over the OTHER sequences (on a tie,
// the smaller geometric mean), checked on hand-made runs whose choice is known; bad inputs
// are refused before any run.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "experiments/loso.h"
#include "solvers/error.h"

using namespace bivo::experiments;

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
