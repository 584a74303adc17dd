// Overlap sums of layers on a canvas, swept row by row, and the least-squares levels they give.
#include "sky/projected_levels.h"

#include <algorithm>
#include <map>
#include <memory>
#include <numeric>

#include "blend/layer_rows.h"
#include "sky/plate_offsets.h"

namespace gdp::sky {
namespace {

// A layer crossing the current row: its reader and this row's values and coverage.
struct OpenLayer {
  int index = 0;
  std::unique_ptr<blending::LayerRows> rows;
  std::vector<float> colour;
  std::vector<unsigned char> covered;
};

// Adds the pixels of row y that both a and b cover.
void add_pair(const OpenLayer& a, const OpenLayer& b, OverlapSum& sum) {
  const blending::Footprint &fa = a.rows->where(), &fb = b.rows->where();
  const int x0 = std::max(fa.x0, fb.x0), x1 = std::min(fa.x1, fb.x1);
  for (int x = x0; x < x1; ++x) {
    const int i = x - fa.x0, j = x - fb.x0;
    if (!a.covered[i] || !b.covered[j]) continue;
    sum.sum += double(a.colour[i]) - b.colour[j];
    ++sum.n;
  }
}

}  // namespace

CanvasLevels canvas_levels(const BlendPlan& plan) {
  const int m = static_cast<int>(plan.layers.size());
  std::vector<blending::Footprint> where(m);
  std::vector<int> order(m);
  for (int k = 0; k < m; ++k) where[k] = blending::footprint(plan, k);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return where[a].y0 < where[b].y0; });
  std::map<std::pair<int, int>, OverlapSum> sums;
  std::vector<OpenLayer> open;
  std::size_t next = 0;
  for (int y = 0; y < plan.canvas.height; ++y) {
    std::erase_if(open, [&](const OpenLayer& l) { return where[l.index].y1 <= y; });
    for (; next < order.size() && where[order[next]].y0 <= y; ++next) {
      const int k = order[next];
      open.push_back({k, std::make_unique<blending::LayerRows>(plan, k, 0, plan.canvas.width, false),
                      std::vector<float>(static_cast<std::size_t>(plan.colour_channels) * where[k].width()),
                      std::vector<unsigned char>(where[k].width())});
    }
    for (OpenLayer& l : open) l.rows->read(y, l.colour, l.covered);
    for (std::size_t a = 0; a < open.size(); ++a)
      for (std::size_t b = a + 1; b < open.size(); ++b) {
        const int i = std::min(open[a].index, open[b].index), j = std::max(open[a].index, open[b].index);
        if (where[i].x1 <= where[j].x0 || where[j].x1 <= where[i].x0) continue;
        OverlapSum& s = sums.try_emplace({i, j}, OverlapSum{i, j}).first->second;
        add_pair(open[a].index == i ? open[a] : open[b], open[a].index == i ? open[b] : open[a], s);
      }
  }
  std::vector<OverlapSum> pairs;
  CanvasLevels levels;
  levels.overlapped.assign(m, 0);
  for (const auto& [key, s] : sums)
    if (s.n > 0) {
      pairs.push_back(s);
      levels.overlapped[s.a] = levels.overlapped[s.b] = 1;
    }
  levels.offsets = offsets_from_overlaps(static_cast<std::size_t>(m), pairs);
  return levels;
}

}  // namespace gdp::sky
