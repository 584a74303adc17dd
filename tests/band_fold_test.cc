// Column runs across a spherical level's fold: every mirrored read has exactly one sender, every fold sum one owner.
#include <gtest/gtest.h>

#include <vector>

#include "bands/band_fold.h"

namespace gdp::bands {
namespace {

BandLayout layout(int width, std::vector<int> bounds) {
  BandLayout L;
  L.bands = static_cast<int>(bounds.size()) - 1;
  L.sweeps = 3;
  L.halo = band_halo(3, 1);
  L.periodic = L.folded = true;
  L.levels = 1;
  L.bounds = {bounds, {}};
  for (int b : bounds) L.bounds[1].push_back(b / 2);
  L.bounds[1].back() = width / 2;
  return L;
}

bool in(const ColumnRuns& runs, int x) {
  for (auto [a, b] : runs)
    if (x >= a && x < b) return true;
  return false;
}

class BandFold : public ::testing::TestWithParam<fem::Mirror> {};

TEST_P(BandFold, EveryMirroredReadHasOneSenderThatOwnsTheColumn) {
  const fem::Mirror side = GetParam();
  const int n = 400;
  const BandLayout L = layout(n, {0, 90, 230, 300, 400});  // unequal bands
  for (int r = 0; r < L.bands; ++r) {
    const FoldPlan mine = fold_reads(L, 0, n, side, r);
    // Every column r stores, read mirrored, comes from exactly one band, which owns it and
    // sends it (its plan's `to` agrees with r's `from`).
    for (int i = L.origin(0, r); i < L.origin(0, r) + L.row_length(0, r); ++i) {
      const int x = fem::mirror_column(side, fem::wrap_index(i, n), n);
      int senders = 0;
      for (int s = 0; s < L.bands; ++s) {
        if (!in(mine.from[s], x)) continue;
        ++senders;
        EXPECT_TRUE(x >= L.begin(0, s) && x < L.end(0, s)) << "band " << s << " sends column " << x << " it does not own";
        EXPECT_TRUE(in(fold_reads(L, 0, n, side, s).to[r], x)) << s << " -> " << r << " column " << x;
      }
      EXPECT_EQ(senders, 1) << "band " << r << " column " << i;
    }
  }
}

TEST_P(BandFold, EveryFoldSumGoesToTheBandOwningItsColumn) {
  const fem::Mirror side = GetParam();
  const int n = 400, m = 200;
  const BandLayout L = layout(n, {0, 90, 230, 300, 400});
  std::vector<int> received(m, 0);
  for (int r = 0; r < L.bands; ++r) {
    const FoldPlan mine = fold_sums(L, 1, m, side, r);
    for (int s = 0; s < L.bands; ++s)
      for (auto [a, b] : mine.from[s])
        for (int x = a; x < b; ++x) {
          ++received[x];
          EXPECT_TRUE(x >= L.begin(1, r) && x < L.end(1, r));
          // It is the mirror image of a column the sender restricts into.
          const int J = fem::mirror_column(side, x, m);
          EXPECT_TRUE(J >= L.begin(1, s) && J < L.end(1, s)) << s << " -> " << r << " column " << x;
          EXPECT_TRUE(in(fold_sums(L, 1, m, side, s).to[r], x));
        }
  }
  for (int x = 0; x < m; ++x) EXPECT_EQ(received[x], 1) << "coarse column " << x;
}

TEST(BandFoldPartners, EqualBandsReadTheirMirrorPartners) {
  const int n = 400;
  const BandLayout L = layout(n, {0, 100, 200, 300, 400});
  // Top: band b reads band 3 - b, and its halo the columns of band 3 - b's neighbours.
  const FoldPlan top = fold_reads(L, 0, n, fem::Mirror::Top, 1);
  ASSERT_EQ(top.from[2].size(), 1u);
  EXPECT_EQ(top.from[2][0], (std::pair{200, 300}));
  // Bottom: (W/2 - 1 - i) mod W maps band 1 (100..200) onto 0..100, band 0.
  const FoldPlan bottom = fold_reads(L, 0, n, fem::Mirror::Bottom, 1);
  ASSERT_EQ(bottom.from[0].size(), 1u);
  EXPECT_EQ(bottom.from[0][0], (std::pair{0, 100}));
  EXPECT_TRUE(bottom.from[2].empty());
}

// A group of bands meeting at its first (a merge's hand-off and take-back, the gathered level):
// what one band sends, the other receives; each band sends its own columns to the first and gets
// back the columns it stores, halo included; bands outside the group take no part.
TEST(BandGroupPlan, EachBandHandsItsOwnColumnsAndTakesBackWhatItStores) {
  const BandLayout L = layout(400, {0, 90, 230, 300, 400});
  const int first = 1, end = 4;
  for (bool to_first : {true, false}) {
    for (int b = 0; b < L.bands; ++b) {
      const FoldPlan p = group_plan(L, 1, b, first, end, to_first);
      for (int s = 0; s < L.bands; ++s) {
        if (s != b) {
          EXPECT_EQ(p.to[s], group_plan(L, 1, s, first, end, to_first).from[b]) << b << " -> " << s;
        }
        const bool in_group = b >= first && b < end && s >= first && s < end;
        const bool linked = in_group && (to_first ? s == first : b == first) && (s != b || b == first);
        const int who = to_first ? b : s;  // the band whose columns these are
        const ColumnRuns want{to_first ? std::pair{L.begin(1, who), L.end(1, who)}
                                       : std::pair{L.origin(1, who), L.origin(1, who) + L.row_length(1, who)}};
        EXPECT_EQ(p.to[s], linked && s != b ? want : ColumnRuns{}) << b << " -> " << s << " " << to_first;
      }
      const bool first_band = b == first;
      EXPECT_EQ(p.from[b].empty(), !first_band) << "only the first takes from itself";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Sides, BandFold, ::testing::Values(fem::Mirror::Top, fem::Mirror::Bottom));

}  // namespace
}  // namespace gdp::bands
