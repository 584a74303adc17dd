// Band layouts: bands that grow too narrow merge in pairs, stage by stage, with boundaries that halve exactly.
#include <gtest/gtest.h>

#include "bands/band_layout.h"
#include "gdp/errors.h"
#include "topology/topology.h"

namespace gdp::bands {
namespace {

multigrid::Hierarchy hierarchy(Domain domain, int w, int h) {
  return multigrid::build_hierarchy(*topology::make_topology(domain), w, h, 0.0, 8);
}

// Every stage: bands cover the level, are wide enough, halve exactly level to level; a merged
// stage's boundaries are every other one of the stage above on its first level (groups of two,
// the last of three when the count is odd).
void check_stages(const multigrid::Hierarchy& h, const BandLayout& top) {
  int level = 0;
  for (const BandLayout* S = &top; S; S = S->merged.get()) {
    SCOPED_TRACE("stage starting at level " + std::to_string(S->first_level));
    EXPECT_EQ(S->first_level, level);
    EXPECT_EQ(S->top(), S == &top);
    ASSERT_GE(S->levels, 1);
    for (int r = 0; r <= S->levels; ++r) {
      ASSERT_EQ(static_cast<int>(S->bounds[r].size()), S->bands + 1);
      EXPECT_EQ(S->bounds[r].front(), 0);
      EXPECT_EQ(S->bounds[r].back(), h.levels[level + r].width());
      for (int b = 0; b < S->bands; ++b) {
        if (r < S->levels) {
          EXPECT_GE(S->end(r, b) - S->begin(r, b), S->min_band_width()) << "level " << level + r;
        }
        if (r > 0 && b > 0) {
          EXPECT_EQ(2 * S->bounds[r][b], S->bounds[r - 1][b]) << "level " << level + r;
        }
      }
    }
    if (S->merged) {
      const BandLayout& M = *S->merged;
      EXPECT_EQ(M.bands, S->bands / 2);
      for (int g = 0; g < M.bands; ++g) {
        EXPECT_EQ(M.bounds[0][g], S->bounds[S->levels][S->group_owner(g)]);
        EXPECT_EQ(S->group_end(g), g + 1 == M.bands ? S->bands : 2 * g + 2);
        for (int b = S->group_owner(g); b < S->group_end(g); ++b) EXPECT_EQ(S->group_of(b), g);
      }
    }
    level += S->levels;
  }
}

TEST(BandLayout, NarrowBandsMergeInPairsStageByStage) {
  const auto h = hierarchy(Domain::Planar, 1024, 256);
  // 8 bands of 128 columns (G = 1, 28 columns at least): levels 0-2 on 8 bands, then 4, 2, 1.
  const BandLayout L = make_band_layout(h, 8, 3, 3, 6);
  check_stages(h, L);
  EXPECT_EQ(L.bands, 8);
  EXPECT_EQ(L.levels, 3);
  ASSERT_TRUE(L.merged);
  EXPECT_EQ(L.merged->bands, 4);
  ASSERT_TRUE(L.merged->merged);
  EXPECT_EQ(L.merged->merged->bands, 2);
  EXPECT_EQ(L.banded_levels(), 6);
  // Where the first level small enough to hold comes first, nothing merges.
  const BandLayout few = make_band_layout(h, 8, 3, 3, 3);
  EXPECT_FALSE(few.merged);
  EXPECT_EQ(few.levels, 3);
}

TEST(BandLayout, OddCountsMergeTheLastThreeBandsTogether) {
  const auto h = hierarchy(Domain::Cylindrical, 1400, 256);
  const BandLayout L = make_band_layout(h, 7, 3, 3, 6);
  check_stages(h, L);
  ASSERT_TRUE(L.merged);
  EXPECT_EQ(L.merged->bands, 3);
  EXPECT_EQ(L.group_of(6), 2);
  EXPECT_EQ(L.group_end(2), 7);
}

TEST(BandLayout, SphericalBandsDoNotMerge) {
  const auto h = hierarchy(Domain::Spherical, 1024, 256);
  const BandLayout L = make_band_layout(h, 8, 3, 3, 6);
  check_stages(h, L);
  EXPECT_FALSE(L.merged);
  EXPECT_EQ(L.levels, 3);  // then gathered
}

TEST(BandLayout, TooNarrowAtTheFinestLevelIsAUsageError) {
  const auto h = hierarchy(Domain::Planar, 200, 64);
  EXPECT_THROW(make_band_layout(h, 8, 3, 3, 6), UsageError);
}

}  // namespace
}  // namespace gdp::bands
