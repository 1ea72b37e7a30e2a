// Experiment plumbing against hand-written expectations: result tables (best per column,
// missing entries, CSV quoting), the log grid of the sweeps, the progress-bar text, the
// profile report's header.
#include <cmath>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "experiments/method_matrix.h"
#include "experiments/parameter_sweep.h"
#include "experiments/profile_study.h"
#include "experiments/progress_bar.h"
#include "experiments/result_table.h"
#include "odometry/kernels/rgbd_kernels.h"
#include "solvers/error.h"

#include <nlohmann/json.hpp>

using namespace bivo;
using namespace bivo::experiments;

TEST(ResultTable, MarksTheSmallestOfEachColumnAndShowsMissingEntries) {
  ResultTable t("method", {"single", "weighted", "bounded"}, {"seq A", "seq B"});
  t.precision = 3;
  t.set(0, 0, 0.125);
  t.set(1, 0, 0.0889);
  t.set(2, 0, 0.0957);
  t.set(0, 1, 0.2);
  t.set(2, 1, 0.1);  // weighted has no value for seq B
  EXPECT_EQ(t.best_row(0), 1);
  EXPECT_EQ(t.best_row(1), 2);
  EXPECT_EQ(t.markdown(),
            "| method | seq A | seq B |\n"
            "|---|---:|---:|\n"
            "| single | 0.125 | 0.200 |\n"
            "| weighted | **0.089** | — |\n"
            "| bounded | 0.096 | **0.100** |\n");
  EXPECT_EQ(t.csv(), "method,seq A,seq B\nsingle,0.125,0.2\nweighted,0.0889,\nbounded,0.0957,0.1\n");
}

TEST(ResultTable, RefusesNonFiniteValuesAndQuotesCsvFields) {
  ResultTable t("m", {"a"}, {"x"});
  EXPECT_THROW(t.set(0, 0, std::nan("")), Error);
  EXPECT_THROW(t.set(0, 0, INFINITY), Error);
  EXPECT_EQ(csv_field("plain"), "plain");
  EXPECT_EQ(csv_field("bounded (ipm-full), v2"), "\"bounded (ipm-full), v2\"");
  EXPECT_EQ(csv_field("say \"hi\""), "\"say \"\"hi\"\"\"");
}

TEST(ParameterSweep, LogGridIsEvenInLog10) {
  const auto g = log_grid(10, 1e6, 6);
  ASSERT_EQ(g.size(), 6u);
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(std::log10(g[i]), 1.0 + i, 1e-12);
  EXPECT_EQ(log_grid(3, 3, 1), std::vector<double>{3});
  EXPECT_THROW(log_grid(0, 1, 3), Error);
  EXPECT_THROW(log_grid(10, 1, 3), Error);
  EXPECT_THROW(log_grid(1, 10, 0), Error);
}

TEST(MethodSpec, ParsesMethodAndOptionalBackend) {
  const MethodSpec a = parse_method_spec("bounded:ipm-full");
  EXPECT_EQ(a.method, "bounded");
  EXPECT_EQ(a.backend, "ipm-full");
  EXPECT_EQ(label(a), "bounded (ipm-full)");
  const MethodSpec b = parse_method_spec("single");
  EXPECT_EQ(b.backend, "");
  EXPECT_EQ(label(b), "single");
}

TEST(ProgressBar, FormatShowsCountRateAndEta) {
  // 45 of 90 after 9 s: 5 it/s, 45 left -> 9 s.
  EXPECT_EQ(ProgressBar::format("seq", 45, 90, 9.0, 10), "seq [#####.....] 45/90  5.0 it/s  ETA 9.0s");
  EXPECT_EQ(ProgressBar::format("seq", 0, 90, 0.0, 4), "seq [....] 0/90");
  ProgressBar off("x", 10, 0);
  EXPECT_FALSE(off.enabled());
}

// The profile report names the kernels its times were measured with, in the text and per row
// of the JSON (timings from different instruction sets are not comparable).
TEST(ProfileReport, NamesTheKernelsBesideTheTimes) {
  ProfileRow row;
  row.method = "weighted";
  row.backend = "gn";
  row.pairs = 3;
  row.total_ms = 4.5;
  row.phase_ms = {{"residuals", 2.0}, {"normal_equations", 1.5}};
  row.iterations_per_level = {1.0, 2.0};
  const std::string dir = ::testing::TempDir() + "/bivo_profile_report";
  const std::string md = write_profile({row}, dir);
  const std::string isa = odometry::to_string(odometry::default_kernels().isa);
  EXPECT_NE(md.find("Per-pixel kernels: " + isa + " "), std::string::npos) << md;
  std::ifstream json(dir + "/profile.json");
  const nlohmann::json j = nlohmann::json::parse(json);
  ASSERT_EQ(j.size(), 1u);
  EXPECT_EQ(j[0].at("kernels"), isa);
  EXPECT_DOUBLE_EQ(j[0].at("total_ms").get<double>(), 4.5);
}
