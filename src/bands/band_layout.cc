// Band boundaries per level and lane widths from the sweep count.
#include "bands/band_layout.h"

#include <algorithm>

#include <fmt/format.h>

#include "gdp/errors.h"

namespace gdp::bands {

BandLayout make_band_layout(const multigrid::Hierarchy& h, bool periodic, int bands, int sweeps, int max_levels,
                            int green_lane, int phase_groups) {
  BandLayout L;
  L.bands = bands;
  L.sweeps = sweeps;
  L.periodic = periodic;
  // Lower G until the finest bands are at least 16 min_band_width() wide: edges that are a large
  // part of a band reorder its rows more (agreement with streaming, tests/bands_test.cc).
  const int finest = h.levels[0].width() / std::max(bands, 1);
  // Spherical rows next to the poles read rows mirrored left to right, columns far from their
  // own: a lead region running G groups ahead would change what they read. One group a phase.
  L.folded = h.levels[0].y.boundary == fem::AxisBoundary::Mirrored;
  L.phase_groups = L.folded ? 1 : std::max(phase_groups, 1);
  while (L.phase_groups > 1 && finest < 16 * L.min_band_width()) L.phase_groups /= 2;
  L.halo = band_halo(sweeps, L.phase_groups);
  L.green_lane = std::max(green_lane, 2 * L.edge());
  const int count = static_cast<int>(h.levels.size());
  const auto fits = [&](int levels) {
    // Boundaries on multiples of 2^(levels - 1), halved level by level.
    const int unit = 1 << std::max(levels - 1, 0);
    const int n = h.levels[0].width();
    std::vector<std::vector<int>> bounds(levels + 1);
    for (int b = 0; b <= bands; ++b) {
      const long long at = static_cast<long long>(n) * b / bands;
      bounds[0].push_back(b == bands ? n : static_cast<int>((at + unit / 2) / unit * unit));
    }
    for (int l = 1; l <= levels; ++l) {
      for (int b = 0; b < bands; ++b) bounds[l].push_back(bounds[l - 1][b] / 2);
      bounds[l].push_back(h.levels[l].width());
    }
    for (int l = 0; l < levels; ++l) {
      if (l > 0 && h.levels[l].width() == h.levels[l - 1].width()) return std::vector<std::vector<int>>{};
      for (int b = 0; b < bands; ++b)
        if (bounds[l][b + 1] - bounds[l][b] < L.min_band_width()) return std::vector<std::vector<int>>{};
    }
    return bounds;
  };
  for (int levels = std::min(max_levels, count - 1); levels >= 1; --levels) {
    auto bounds = fits(levels);
    if (bounds.empty()) continue;
    L.levels = levels;
    L.bounds = std::move(bounds);
    return L;
  }
  throw UsageError(fmt::format("{} bands need an image at least {} pixels wide ({} per band with {} sweeps), got {}",
                               bands, bands * L.min_band_width(), L.min_band_width(), sweeps, h.levels[0].width()));
}

}  // namespace gdp::bands
