// Overlap sums of layers on a canvas, swept row by row: the least-squares levels and, sampled on a grid, the smooth backgrounds they give.
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

// A pair's overlap: the sum of a - b, and (with a fit) the sums of each layer's smooth basis
// functions over the same pixels, which correct the sum once the smooth terms are known.
struct PairSums {
  OverlapSum sum;
  std::array<double, 4> basis_a{}, basis_b{};
};

// What the sweep gathers: each pair's sums, and the sampled equations of the fit.
class OverlapSweep {
 public:
  OverlapSweep(const BlendPlan& plan, std::vector<blending::Footprint> where, bool fit)
      : plan_(plan), where_(std::move(where)), fit_(fit) {
    int smallest = 1 << 30;
    for (const PlacedLayer& l : plan.layers) smallest = std::min(smallest, std::max(l.width, l.height));
    stride_ = std::max(1, smallest / 64);
  }

  // The pixels of row y that both a and b cover.
  void add_pair(int y, const OpenLayer& a, const OpenLayer& b) {
    const blending::Footprint &fa = where_[a.index], &fb = where_[b.index];
    const int x0 = std::max(fa.x0, fb.x0), x1 = std::min(fa.x1, fb.x1);
    PairSums& s = sums_.try_emplace({a.index, b.index}, PairSums{{a.index, b.index}}).first->second;
    const bool sampled_row = fit_ && y % stride_ == 0;
    for (int x = x0; x < x1; ++x) {
      const int i = x - fa.x0, j = x - fb.x0;
      if (!a.covered[i] || !b.covered[j]) continue;
      const double d = double(a.colour[i]) - b.colour[j];
      s.sum.sum += d;
      ++s.sum.n;
      if (!fit_) continue;
      const auto pa = basis(a.index, i, y), pb = basis(b.index, j, y);
      for (int t = 0; t < 4; ++t) {
        s.basis_a[t] += pa[t];
        s.basis_b[t] += pb[t];
      }
      if (sampled_row && x % stride_ == 0) equations_.push_back({a.index, b.index, pa, pb, d});
    }
  }

  const std::map<std::pair<int, int>, PairSums>& sums() const { return sums_; }
  const std::vector<BackgroundEquation>& equations() const { return equations_; }

 private:
  // Layer k's basis at the pixel i of its footprint's columns on canvas row y (its own pixel centre).
  std::array<double, 4> basis(int k, int i, int y) const {
    const blending::Footprint& f = where_[k];
    const PlacedLayer& l = plan_.layers[k];
    return background_basis(l.width, l.height, i + f.skip_x + 0.5, y - f.y0 + f.skip_y + 0.5);
  }

  const BlendPlan& plan_;
  std::vector<blending::Footprint> where_;
  bool fit_;
  int stride_ = 1;
  std::map<std::pair<int, int>, PairSums> sums_;
  std::vector<BackgroundEquation> equations_;
};

// Reads the layers top to bottom, a row of each open layer at a time, into the sweep.
void sweep_layers(const BlendPlan& plan, const std::vector<blending::Footprint>& where, OverlapSweep& sweep) {
  const int m = static_cast<int>(plan.layers.size());
  std::vector<int> order(m);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return where[a].y0 < where[b].y0; });
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
        const bool first = open[a].index < open[b].index;
        const OpenLayer &lo = first ? open[a] : open[b], &hi = first ? open[b] : open[a];
        if (where[lo.index].x1 <= where[hi.index].x0 || where[hi.index].x1 <= where[lo.index].x0) continue;
        sweep.add_pair(y, lo, hi);
      }
  }
}

}  // namespace

CanvasLevels canvas_levels(const BlendPlan& plan, double damping) {
  const int m = static_cast<int>(plan.layers.size());
  std::vector<blending::Footprint> where(m);
  for (int k = 0; k < m; ++k) where[k] = blending::footprint(plan, k);
  OverlapSweep sweep(plan, where, damping >= 0.0);
  sweep_layers(plan, where, sweep);
  CanvasLevels levels;
  if (damping >= 0.0) {
    std::vector<std::array<double, 4>> energy;
    for (const PlacedLayer& l : plan.layers) energy.push_back(background_energy(l.width, l.height));
    const std::vector<BackgroundEquation>& equations = sweep.equations();
    levels.backgrounds = fit_backgrounds(
        energy, [&](const auto& each) { std::for_each(equations.begin(), equations.end(), each); }, damping);
  }
  std::vector<OverlapSum> pairs;
  levels.overlapped.assign(m, 0);
  for (const auto& [key, s] : sweep.sums()) {
    if (s.sum.n == 0) continue;
    OverlapSum corrected = s.sum;
    if (!levels.backgrounds.empty()) {  // the mean of (a - S_a) - (b - S_b) over the overlap
      const PlateBackground &a = levels.backgrounds[s.sum.a], &b = levels.backgrounds[s.sum.b];
      corrected.sum -= a.slope_u * s.basis_a[1] + a.slope_v * s.basis_a[2] + a.radial * s.basis_a[3];
      corrected.sum += b.slope_u * s.basis_b[1] + b.slope_v * s.basis_b[2] + b.radial * s.basis_b[3];
    }
    pairs.push_back(corrected);
    levels.overlapped[s.sum.a] = levels.overlapped[s.sum.b] = 1;
  }
  levels.offsets = offsets_from_overlaps(static_cast<std::size_t>(m), pairs);
  return levels;
}

LayerBackground layer_background(const PlacedLayer& layer, const PlateBackground& smooth) {
  LayerBackground b;
  b.cx = layer.width / 2.0;
  b.cy = layer.height / 2.0;
  b.scale = std::max(layer.width, layer.height);
  b.slope_u = smooth.slope_u;
  b.slope_v = smooth.slope_v;
  b.radial = smooth.radial;
  // background_basis's radial term is u^2 + v^2 less its mean over the layer: at the centre, -mean.
  b.constant = smooth.radial * background_basis(layer.width, layer.height, b.cx, b.cy)[3];
  return b;
}

}  // namespace gdp::sky
