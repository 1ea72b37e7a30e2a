// The claim-by-claim table (experiments/paper_claims.h) on a hand-made MethodMatrix: the
// paper's constants are compared with the matrix's numbers, and "holds" follows the numbers.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "experiments/paper_claims.h"

using namespace bivo::experiments;

namespace {

MethodMatrix matrix(double single_nt, double weighted_nt, double single_t, double weighted_t) {
  MethodMatrix m;
  m.sequences = {"rgbd_dataset_freiburg3_synth_structure_notexture_near",
                 "rgbd_dataset_freiburg3_structure_texture_near"};
  m.methods = {MethodSpec{"single", ""}, MethodSpec{"weighted", ""}};
  const double rpe[2][2] = {{single_nt, single_t}, {weighted_nt, weighted_t}};
  for (int r = 0; r < 2; ++r) {
    for (int c = 0; c < 2; ++c) {
      MatrixCell cell;
      cell.sequence = m.sequences[c];
      cell.spec = m.methods[r];
      bivo::odometry::io::RpeResult e;
      e.trans_rmse = rpe[r][c];
      cell.rpe = e;
      m.cells.push_back(cell);
    }
  }
  return m;
}

const ClaimRow* find(const std::vector<ClaimRow>& rows, const std::string& claim, const std::string& category) {
  for (const auto& r : rows) {
    if (r.claim.find(claim) != std::string::npos && r.category == category) return &r;
  }
  return nullptr;
}

}  // namespace

TEST(PaperClaims, CategoryIsReadFromRealAndSyntheticNames) {
  EXPECT_EQ(category_of("rgbd_dataset_freiburg3_synth_nostructure_notexture_far"), "nostructure_notexture_far");
  EXPECT_EQ(category_of("rgbd_dataset_freiburg3_structure_texture_near"), "structure_texture_near");
  EXPECT_EQ(category_of("rgbd_dataset_freiburg3_nostructure_texture_near_withloop"), "nostructure_texture_near");
  EXPECT_EQ(category_of("rgbd_dataset_freiburg1_rpy"), "");
}

TEST(PaperClaims, RowsFollowTheNumbers) {
  // Table 1: weighted 0.088853 vs single 0.125235 on structure_notexture (better), 0.015101 vs
  // 0.015956 on structure_texture (better).
  const auto good = paper_claims(matrix(0.10, 0.05, 0.010, 0.009));
  const ClaimRow* nt = find(good, "weighted better than single", "structure_notexture_near");
  ASSERT_NE(nt, nullptr);
  EXPECT_EQ(nt->source, "table 1");
  EXPECT_NE(nt->paper.find("0.0889 vs 0.1252"), std::string::npos) << nt->paper;
  EXPECT_EQ(nt->bivo, "0.0500 vs 0.1000 (0.50x)");
  // RPE over other windows than the paper's 1 s: bivo's values say their unit.
  MethodMatrix short_windows = matrix(0.10, 0.05, 0.010, 0.009);
  short_windows.rpe_delta = 0.1;
  const auto short_rows = paper_claims(short_windows);
  const ClaimRow* nt_short = find(short_rows, "weighted better than single", "structure_notexture_near");
  ASSERT_NE(nt_short, nullptr);
  EXPECT_EQ(nt_short->bivo, "0.0500 vs 0.1000 (0.50x) [m per 0.1 s]");
  EXPECT_TRUE(nt->holds);
  const ClaimRow* drop = find(good, "without texture", "structure_notexture_near / structure_texture_near");
  ASSERT_NE(drop, nullptr);
  EXPECT_EQ(drop->paper, "7.85x");  // 0.125235 / 0.015956, table 1
  EXPECT_TRUE(drop->holds);         // 10x
  // The same matrix with weighted worse than single and no texture drop: the claims fail.
  const auto bad = paper_claims(matrix(0.012, 0.02, 0.010, 0.011));
  EXPECT_FALSE(find(bad, "weighted better than single", "structure_notexture_near")->holds);
  EXPECT_FALSE(find(bad, "weighted better than single", "structure_texture_near")->holds);
  EXPECT_FALSE(find(bad, "without texture", "structure_notexture_near / structure_texture_near")->holds);
  const std::string md = claims_markdown(bad);
  EXPECT_NE(md.find("does not hold"), std::string::npos);
  EXPECT_NE(md.find("0 of "), std::string::npos) << md;
}
