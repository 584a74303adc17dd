// Where the bands lie on every level, and the lanes inside them (docs/how-bands-work.md).
#pragma once

#include <vector>

#include "multigrid/hierarchy.h"

namespace gdp::bands {

struct BandLayout {
  int bands = 1;
  int sweeps = 3;        // k: Gauss-Seidel sweeps per pass
  int halo = 4;          // columns kept of each neighbour: max(2k, 4)
  int edge_lane = 0;     // width of the red and blue lanes
  int green_lane = 0;    // the green lane is split into lanes of about this width (cache locality)
  int levels = 0;        // levels 0 .. levels - 1 are banded; level `levels` is gathered to worker 0
  bool periodic = false;
  // bounds[l][b] .. bounds[l][b + 1]: the columns band b owns on level l (l = 0 .. levels).
  std::vector<std::vector<int>> bounds;

  int begin(int l, int b) const { return bounds[l][b]; }
  int end(int l, int b) const { return bounds[l][b + 1]; }
  int origin(int l, int b) const { return begin(l, b) - halo; }              // global column of a row's [0]
  int row_length(int l, int b) const { return end(l, b) - begin(l, b) + 2 * halo; }
  int left(int b) const { return b > 0 ? b - 1 : periodic ? bands - 1 : -1; }   // -1: none
  int right(int b) const { return b + 1 < bands ? b + 1 : periodic ? 0 : -1; }
  // 2(k - s): how far sweep s's tiles are shifted (section 6.2); s = 1 .. k.
  int shift(int s) const { return 2 * (sweeps - s); }
  // The narrowest band a level may have.
  int min_band_width() const { return 2 * edge_lane + 4; }
};

// Bands of (nearly) equal width, boundaries on multiples of 2^(levels - 1) so that each level's
// bands halve into the next one's. Levels are banded while every band stays at least
// min_band_width() wide, and at most up to `max_levels` (the first level small enough to hold
// whole); the rest run on worker 0. Throws UsageError when even the finest level is too narrow.
BandLayout make_band_layout(const multigrid::Hierarchy& h, bool periodic, int bands, int sweeps, int max_levels,
                            int green_lane = 4096);

}  // namespace gdp::bands
