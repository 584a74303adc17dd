// Tone mapping's first pass: the log-luminance pyramid (levels >= 1 kept in row stores) and mean gradients.
#pragma once

#include <memory>
#include <vector>

#include "gdp/rows.h"
#include "gdp/topology.h"
#include "schedule/row_store.h"

namespace gdp::apps::tonemap {

struct Pyramid {
  int levels = 0;                     // level 0 is the input's own resolution
  std::vector<int> widths, heights;
  std::vector<double> mean_gradient;  // mean |grad H| of each level, in that level's pixels
  // Log luminance of levels 1..levels-1, in row order (entry 0 is empty: level 0 is the input).
  std::vector<std::unique_ptr<schedule::RowStore<float>>> rows;
};

// Levels a width x height image gets when `requested` is 0: halve while the short side of the
// next level stays at least 32 pixels. Otherwise `requested`, capped so no level is empty.
int pyramid_levels(int width, int height, int requested);

// One pass over `in` (from row 0; not rewound): every level is made from the one above as its
// rows arrive, a few rows of each in memory, and written to its store (in memory or an
// unlinked scratch file, by `policy`).
Pyramid build_pyramid(RowReader& in, Domain domain, int levels, const schedule::StorePolicy& policy);

}  // namespace gdp::apps::tonemap
