// Under mpirun: seams computed once by rank 0 and shared, and the layers' overlaps gathered from every rank.
#pragma once

#include <vector>

#include "blend/seams.h"

namespace gdp::blending {

// Whether this process is one of several mpirun ranks (MPI started, more than one rank).
bool several_ranks();

// Rank 0's `labels` (filled) to every other rank's `labels` (the same size), in blocks of rows.
// Every rank calls it at the same point; the others wait without holding a core. Without several
// ranks: nothing.
void share_labels(LabelPlane& labels);

// `overlaps` (per layer: 1 some pixel of it another layer covers too, 0 none seen, -1 unknown) as
// the largest over the ranks: a layer overlaps another if some rank saw it do so, and when the
// ranks' columns cover the canvas the rest are exactly the isolated ones. Every rank calls it at
// the same point. Without several ranks: unchanged.
void gather_overlaps(std::vector<signed char>& overlaps);

}  // namespace gdp::blending
