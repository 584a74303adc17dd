// Band boundaries per level and lane widths from the sweep count.
#include "bands/band_layout.h"

#include <algorithm>

#include <fmt/format.h>

#include "gdp/errors.h"

namespace gdp::bands {

BandLayout make_band_layout(const multigrid::Hierarchy& h, bool periodic, int bands, SweepCounts sweeps, int max_levels,
                            int green_lane, int phase_groups) {
  BandLayout L;
  L.bands = bands;
  L.sweeps = sweeps.most();  // the geometry fits both passes; each stage gets pre and post below
  L.post_sweeps = sweeps.most();
  L.periodic = periodic;
  // Lower G until the finest bands are at least 16 min_band_width() wide: edges that are a large
  // part of a band reorder its rows more (agreement with streaming, tests/bands_test.cc).
  const int finest = h.levels[0].width() / std::max(bands, 1);
  // Spherical rows next to the poles read rows mirrored left to right, columns far from their
  // own: a lead region running G groups ahead would change what they read. One group a phase.
  L.folded = h.levels[0].y.boundary == fem::AxisBoundary::Mirrored;
  L.phase_groups = L.folded ? 1 : std::max(phase_groups, 1);
  while (L.phase_groups > 1 && finest < 16 * L.min_band_width()) L.phase_groups /= 2;
  L.halo = band_halo(sweeps.most(), L.phase_groups);
  L.green_lane = std::max(green_lane, 2 * L.edge());
  const int count = static_cast<int>(h.levels.size()), n = h.levels[0].width();
  // The stages for `total` banded levels: each stage's band boundaries on level 0 (multiples of
  // 2^(total - 1), so they halve exactly through every banded level) and its first level; empty
  // where some banded level cannot have bands wide enough.
  struct Stage {
    int start;
    std::vector<int> cuts;
  };
  const auto bound = [&](const std::vector<int>& cuts, int i, int l) {
    return i + 1 == static_cast<int>(cuts.size()) ? h.levels[l].width() : cuts[i] >> l;
  };
  const auto narrow = [&](const std::vector<int>& cuts, int l) {
    for (std::size_t i = 0; i + 1 < cuts.size(); ++i)
      if (bound(cuts, static_cast<int>(i) + 1, l) - bound(cuts, static_cast<int>(i), l) < L.min_band_width()) return true;
    return false;
  };
  const auto stages = [&](int total) {
    const int unit = 1 << std::max(total - 1, 0);
    std::vector<int> cuts;
    for (int b = 0; b <= bands; ++b) {
      const long long at = static_cast<long long>(n) * b / bands;
      cuts.push_back(b == bands ? n : static_cast<int>((at + unit / 2) / unit * unit));
    }
    std::vector<Stage> chain{{0, cuts}};
    for (int l = 0; l < total; ++l) {
      if (l > 0 && h.levels[l].width() == h.levels[l - 1].width()) return std::vector<Stage>{};
      const std::vector<int>& now = chain.back().cuts;
      if (!narrow(now, l)) continue;
      const int have = static_cast<int>(now.size()) - 1;
      if (l == chain.back().start || L.folded || have == 1) return std::vector<Stage>{};
      std::vector<int> merged;  // pairs; the last group takes three bands when the count is odd
      for (int g = 0; g < have / 2; ++g) merged.push_back(now[2 * g]);
      merged.push_back(n);
      if (narrow(merged, l)) return std::vector<Stage>{};
      chain.push_back({l, std::move(merged)});
    }
    return chain;
  };
  for (int total = std::min(max_levels, count - 1); total >= 1; --total) {
    const std::vector<Stage> chain = stages(total);
    if (chain.empty()) continue;
    std::shared_ptr<const BandLayout> below;
    for (int i = static_cast<int>(chain.size()) - 1; i >= 0; --i) {
      auto S = std::make_shared<BandLayout>(L);
      const int start = chain[i].start, end = i + 1 < static_cast<int>(chain.size()) ? chain[i + 1].start : total;
      S->bands = static_cast<int>(chain[i].cuts.size()) - 1;
      S->first_level = start;
      S->levels = end - start;
      S->merged = below;
      S->sweeps = sweeps.pre;
      S->post_sweeps = sweeps.post;
      S->bounds.assign(S->levels + 1, {});
      for (int r = 0; r <= S->levels; ++r)
        for (int b = 0; b <= S->bands; ++b) S->bounds[r].push_back(bound(chain[i].cuts, b, start + r));
      below = S;
    }
    return *below;
  }
  throw UsageError(fmt::format("{} bands need an image at least {} pixels wide ({} per band with {} sweeps), got {}",
                               bands, bands * L.min_band_width(), L.min_band_width(), sweeps.most(), h.levels[0].width()));
}

BandLayout single_band_layout(const multigrid::Hierarchy& h, bool periodic, SweepCounts sweeps, int levels) {
  BandLayout L;
  L.single = true;
  L.sweeps = sweeps.pre;
  L.post_sweeps = sweeps.post;
  L.periodic = periodic;
  L.halo = 0;
  L.levels = levels;
  for (int l = 0; l <= levels; ++l) L.bounds.push_back({0, h.levels[l].width()});
  return L;
}

}  // namespace gdp::bands
