// Band boundaries per level and lane widths from the sweep count.
#include "bands/band_layout.h"

#include <algorithm>

#include <fmt/format.h>

#include "gdp/errors.h"

namespace gdp::bands {

BandLayout make_band_layout(const multigrid::Hierarchy& h, int bands, int pre, int post, int max_levels) {
  // The geometry fits both passes (the larger sweep count); each stage gets pre and post below.
  BandLayout L{.bands = bands, .sweeps = std::max(pre, post), .bounds = {}, .merged = {}};
  L.periodic = h.levels[0].x.boundary == fem::AxisBoundary::Periodic;
  // Spherical rows next to the poles read rows mirrored left to right, columns far from their
  // own: a lead region running G groups ahead would change what they read. One group a phase.
  L.folded = h.levels[0].y.boundary == fem::AxisBoundary::Mirrored;
  L.phase_groups = L.folded ? 1 : kDefaultPhaseGroups;
  // Lower G until the finest bands are at least 16 min_band_width() wide: edges that are a large
  // part of a band reorder its rows more (agreement with streaming, tests/bands_test.cc).
  const int n = h.levels[0].width();
  while (L.phase_groups > 1 && n / bands < 16 * L.min_band_width()) L.phase_groups /= 2;
  L.halo = band_halo(L.sweeps, L.phase_groups);
  L.green_lane = std::max(4096, 2 * L.edge());
  // The band boundaries on level l of a stage whose level-0 boundaries are `cuts` (multiples of
  // 2^(total - 1), so they halve exactly through every banded level).
  const auto bounds = [&](const std::vector<int>& cuts, int l) {
    std::vector<int> at;
    for (std::size_t i = 0; i + 1 < cuts.size(); ++i) at.push_back(cuts[i] >> l);
    at.push_back(h.levels[l].width());
    return at;
  };
  const auto narrow = [&](const std::vector<int>& at) {
    const auto closer = [&](int a, int b) { return b - a < L.min_band_width(); };
    return std::adjacent_find(at.begin(), at.end(), closer) != at.end();
  };
  // The stage of bands `cuts` from level `start` on, banded down to level `total` and merging where
  // they grow too narrow; null where some banded level cannot have bands wide enough.
  const auto stage = [&](const auto& self, const std::vector<int>& cuts, int start,
                         int total) -> std::shared_ptr<const BandLayout> {
    int end = start;  // this stage's levels: [start, end)
    std::shared_ptr<const BandLayout> below;
    for (; end < total; ++end) {
      if (end > 0 && h.levels[end].width() == h.levels[end - 1].width()) return nullptr;
      if (!narrow(bounds(cuts, end))) continue;
      const int have = static_cast<int>(cuts.size()) - 1;
      if (end == start || L.folded || have == 1) return nullptr;
      std::vector<int> merged;  // pairs; the last group takes three bands when the count is odd
      for (int g = 0; g < have / 2; ++g) merged.push_back(cuts[2 * g]);
      merged.push_back(n);
      if (!(below = self(self, merged, end, total))) return nullptr;
      break;
    }
    auto S = std::make_shared<BandLayout>(L);
    S->bands = static_cast<int>(cuts.size()) - 1;
    S->first_level = start;
    S->levels = end - start;
    S->merged = below;
    S->sweeps = pre;
    S->post_sweeps = post;
    for (int l = start; l <= end; ++l) S->bounds.push_back(bounds(cuts, l));
    return S;
  };
  for (int total = std::min(max_levels, static_cast<int>(h.levels.size()) - 1); total >= 1; --total) {
    const int unit = 1 << (total - 1);
    std::vector<int> cuts;
    for (int b = 0; b <= bands; ++b) {
      const long long at = static_cast<long long>(n) * b / bands;
      cuts.push_back(b == bands ? n : static_cast<int>((at + unit / 2) / unit * unit));
    }
    if (const auto top = stage(stage, cuts, 0, total)) return *top;
  }
  throw UsageError(fmt::format("{} bands need an image at least {} pixels wide ({} per band with {} sweeps), got {}",
                               bands, bands * L.min_band_width(), L.min_band_width(), L.sweeps, n));
}

BandLayout single_band_layout(const multigrid::Hierarchy& h, int pre, int post, int levels) {
  BandLayout L{.sweeps = pre, .post_sweeps = post, .halo = 0, .levels = levels, .single = true, .bounds = {}, .merged = {}};
  L.periodic = h.levels[0].x.boundary == fem::AxisBoundary::Periodic;
  for (int l = 0; l <= levels; ++l) L.bounds.push_back({0, h.levels[l].width()});
  return L;
}

}  // namespace gdp::bands
