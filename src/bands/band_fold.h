// Which columns bands exchange besides strips: a spherical level's first and last two rows read rows
// mirrored left to right (docs/sphere-solver.md), at columns other bands own; a merge's rows.
#pragma once

#include <utility>
#include <vector>

#include "bands/band_layout.h"
#include "fem/axis.h"

namespace gdp::bands {

// Runs [begin, end) of columns of a row of n samples, in increasing order.
using ColumnRuns = std::vector<std::pair<int, int>>;

// One exchange of column runs between bands (across the fold, or at a merge), seen by one band:
// the columns it sends to band b (to[b]) and receives from band b (from[b]); from[band] is what it
// takes from itself.
struct FoldPlan {
  std::vector<ColumnRuns> to, from;
};

// Rows across the fold on banded level l (n columns): a band shows the columns it owns to every
// band that stores (halo included) their mirror image.
FoldPlan fold_reads(const BandLayout& L, int l, int n, fem::Mirror side, int band);

// Restriction into level l (banded or the gathered one, n columns) across the fold: a band's
// contributions to the mirror image of its own columns go to the bands that own them.
FoldPlan fold_sums(const BandLayout& L, int l, int n, fem::Mirror side, int band);

// Bands [first, end) of level l meet at band `first`: each sends it its own columns (`to_first`) or
// gets back from it the columns it stores, halo included (a merge's hand-off and take-back, the
// level below the bands gathered to band 0).
FoldPlan group_plan(const BandLayout& L, int l, int band, int first, int end, bool to_first);

}  // namespace gdp::bands
