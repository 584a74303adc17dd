// Graph-cut seams: alpha-expansion on a coarse grid of the canvas, then at full resolution in a band around the coarse seams.
#include "blend/graphcut_seams.h"

#include <algorithm>
#include <cmath>

#include "blend/layer_window.h"
#include "blend/seam_grid.h"

namespace gdp::blending {
namespace {

// The layers on a grid of k x k cells: each layer's mean colour per cell, `covers` where it
// covers the whole cell. Memory: (4 x channels + 5) bytes per cell of each layer.
struct CoarseGrid {
  int k = 1, width = 0, height = 0;
  std::vector<Patch> patches;
};

CoarseGrid coarse_layers(const BlendPlan& plan, int k, const std::function<void(double)>& progress) {
  const int n = static_cast<int>(plan.layers.size()), c = plan.colour_channels;
  const int W = plan.canvas.width, H = plan.canvas.height;
  CoarseGrid g;
  g.k = k;
  g.width = (W + k - 1) / k;
  g.height = (H + k - 1) / k;
  g.patches.resize(n);
  std::vector<std::vector<int>> counts(n);
  for (int l = 0; l < n; ++l) {
    const Footprint f = footprint(plan, l);
    Patch& p = g.patches[l];
    p.x0 = f.x0 / k;
    p.y0 = f.y0 / k;
    p.w = f.width() > 0 ? (f.x1 + k - 1) / k - p.x0 : 0;
    p.h = f.y1 > f.y0 ? (f.y1 + k - 1) / k - p.y0 : 0;
    p.colour.assign(static_cast<std::size_t>(p.w) * p.h * c, 0.0f);
    p.covers.assign(static_cast<std::size_t>(p.w) * p.h, 0);
    counts[l].assign(p.covers.size(), 0);
  }
  LayerWindow window(plan);
  for (int y = 0; y < H; ++y) {
    window.slide(y, y + 1);
    for (int l = 0; l < n; ++l) {
      const Patch* row = window.layers()[l];
      if (!row) continue;
      Patch& p = g.patches[l];
      const std::size_t cell_row = static_cast<std::size_t>(y / k - p.y0) * p.w;
      for (int x = row->x0; x < row->x0 + row->w; ++x) {
        if (!row->has(x, y)) continue;
        const std::size_t cell = cell_row + (x / k - p.x0);
        ++counts[l][cell];
        const float* v = row->at(x, y, c);
        for (int ch = 0; ch < c; ++ch) p.colour[cell * c + ch] += v[ch];
      }
    }
    if (progress) progress(static_cast<double>(y + 1) / H);
  }
  for (int l = 0; l < n; ++l) {
    Patch& p = g.patches[l];
    for (int cy = p.y0; cy < p.y0 + p.h; ++cy)
      for (int cx = p.x0; cx < p.x0 + p.w; ++cx) {
        const std::size_t cell = static_cast<std::size_t>(cy - p.y0) * p.w + (cx - p.x0);
        const int area = (std::min((cx + 1) * k, W) - cx * k) * (std::min((cy + 1) * k, H) - cy * k);
        const int count = counts[l][cell];
        p.covers[cell] = count == area;
        for (int ch = 0; ch < c && count > 0; ++ch) p.colour[cell * c + ch] /= static_cast<float>(count);
      }
  }
  return g;
}

// The coarse labels: the depth seams' label at each cell's centre where that layer covers the
// cell, else the first layer that does (else the depth label, fixed). Cells two or more layers
// cover are free; `band` marks cells no layer wholly covers (refined at full resolution).
SeamGrid coarse_labels(const BlendPlan& plan, const CoarseGrid& cg, const LabelPlane& depth, bool wrap_x,
                       std::vector<unsigned char>& band) {
  const int W = plan.canvas.width, H = plan.canvas.height, k = cg.k;
  SeamGrid g;
  g.width = cg.width;
  g.height = cg.height;
  g.channels = plan.colour_channels;
  g.wrap_x = wrap_x;
  for (const Patch& p : cg.patches) g.layers.push_back(p.w > 0 && p.h > 0 ? &p : nullptr);
  const std::size_t cells = static_cast<std::size_t>(g.width) * g.height;
  std::vector<unsigned char> count(cells, 0);
  std::vector<Label> first(cells, 0);
  for (std::size_t l = 0; l < cg.patches.size(); ++l) {
    const Patch& p = cg.patches[l];
    for (int cy = p.y0; cy < p.y0 + p.h; ++cy)
      for (int cx = p.x0; cx < p.x0 + p.w; ++cx) {
        if (!p.has(cx, cy)) continue;
        const std::size_t i = static_cast<std::size_t>(cy) * g.width + cx;
        count[i] = static_cast<unsigned char>(std::min(2, count[i] + 1));
        if (!first[i]) first[i] = static_cast<Label>(l + 1);
      }
  }
  g.labels.resize(cells);
  g.free.resize(cells);
  band.assign(cells, 0);
  std::vector<Label> row(W);
  for (int cy = 0; cy < g.height; ++cy) {
    depth.read_row(std::min(cy * k + k / 2, H - 1), row);
    for (int cx = 0; cx < g.width; ++cx) {
      const std::size_t i = static_cast<std::size_t>(cy) * g.width + cx;
      const Label d = row[std::min(cx * k + k / 2, W - 1)];
      const bool d_covers = d && g.layers[d - 1] && g.layers[d - 1]->has(cx, cy);
      g.labels[i] = d_covers || !first[i] ? d : first[i];
      g.free[i] = count[i] >= 2;
      band[i] = !first[i];
    }
  }
  return g;
}

// Cells within one cell (8-neighbourhood) of a seam between two layers, added to `band`.
void mark_band(const SeamGrid& g, std::vector<unsigned char>& band) {
  for (int r = 0; r < g.height; ++r)
    for (int x = 0; x < g.width; ++x) {
      const Label l = g.label(x, r);
      for (int dr = -1; dr <= 1 && l; ++dr)
        for (int dx = -1; dx <= 1; ++dx) {
          int qx = x + dx;
          const int qr = r + dr;
          if (g.wrap_x) qx = (qx + g.width) % g.width;
          if (qx < 0 || qx >= g.width || qr < 0 || qr >= g.height) continue;
          const Label q = g.label(qx, qr);
          if (q && q != l) band[static_cast<std::size_t>(r) * g.width + x] = 1;
        }
    }
}

// Full resolution, strip by strip: rows [y0, y1) are refined with `lookahead` rows below them
// (refined too, then dropped) and the row above fixed at its final labels.
class Refinement {
 public:
  Refinement(const BlendPlan& plan, const SeamGrid& coarse, const std::vector<unsigned char>& band, int k,
             const LabelPlane& depth, bool wrap_x)
      : plan_(plan), coarse_(coarse), band_(band), k_(k), depth_(depth), wrap_x_(wrap_x), window_(plan) {}

  void run(LabelPlane& out, const std::function<void(double)>& progress) {
    const int H = plan_.canvas.height, W = plan_.canvas.width;
    const int strip = std::max(64, 4 * k_), lookahead = std::max(32, 2 * k_);
    std::vector<Label> above;
    for (int y0 = 0; y0 < H; y0 += strip) {
      const int y1 = std::min(H, y0 + strip), end = std::min(H, y1 + lookahead), top = y0 > 0 ? y0 - 1 : 0;
      window_.slide(top, end);
      SeamGrid g = grid(top, end, y0, above);
      expand_labels(g);
      for (int y = y0; y < y1; ++y)
        out.write_row(y, std::span<const Label>(g.labels.data() + static_cast<std::size_t>(y - top) * W, W));
      above.assign(g.labels.begin() + static_cast<std::ptrdiff_t>(y1 - 1 - top) * W,
                   g.labels.begin() + static_cast<std::ptrdiff_t>(y1 - top) * W);
      if (progress) progress(static_cast<double>(y1) / H);
    }
  }

 private:
  // Rows [top, end): the row above y0 fixed at `above`; the others start from the coarse label
  // where that layer covers the pixel, else the depth label; free in the band where 2+ layers cover.
  SeamGrid grid(int top, int end, int y0, const std::vector<Label>& above) {
    const int W = plan_.canvas.width;
    SeamGrid g;
    g.width = W;
    g.height = end - top;
    g.row0 = top;
    g.channels = plan_.colour_channels;
    g.wrap_x = wrap_x_;
    g.layers = window_.layers();
    const std::size_t cells = static_cast<std::size_t>(W) * g.height;
    g.labels.assign(cells, 0);
    g.free.assign(cells, 0);
    std::vector<unsigned char> count(cells, 0);
    for (const Patch* p : g.layers) {
      if (!p) continue;
      for (int y = std::max(top, p->y0); y < std::min(end, p->y0 + p->h); ++y)
        for (int x = p->x0; x < p->x0 + p->w; ++x)
          if (p->has(x, y)) {
            unsigned char& c = count[static_cast<std::size_t>(y - top) * W + x];
            c = static_cast<unsigned char>(std::min(2, c + 1));
          }
    }
    std::vector<Label> depth(W);
    for (int y = top; y < end; ++y) {
      Label* l = g.labels.data() + static_cast<std::size_t>(y - top) * W;
      if (y < y0) {
        std::copy(above.begin(), above.end(), l);
        continue;
      }
      depth_.read_row(y, depth);
      for (int x = 0; x < W; ++x) {
        const std::size_t cell = static_cast<std::size_t>(y / k_) * coarse_.width + x / k_;
        const Label c = coarse_.labels[cell];
        l[x] = c && g.layers[c - 1] && g.layers[c - 1]->has(x, y) ? c : depth[x];
        g.free[static_cast<std::size_t>(y - top) * W + x] = band_[cell] && count[static_cast<std::size_t>(y - top) * W + x] >= 2;
      }
    }
    return g;
  }

  const BlendPlan& plan_;
  const SeamGrid& coarse_;
  const std::vector<unsigned char>& band_;
  int k_;
  const LabelPlane& depth_;
  bool wrap_x_;
  LayerWindow window_;
};

}  // namespace

std::vector<double> seam_costs(const BlendPlan& plan, const std::vector<const LabelPlane*>& planes, bool wrap_x) {
  const int W = plan.canvas.width, H = plan.canvas.height;
  std::vector<double> sums(planes.size(), 0.0);
  LayerWindow window(plan);
  std::vector<std::vector<Label>> previous(planes.size(), std::vector<Label>(W));
  for (int y = 0; y < H; ++y) {
    const int top = std::max(0, y - 1);
    window.slide(top, y + 1);
    for (std::size_t i = 0; i < planes.size(); ++i) {
      SeamGrid g;
      g.width = W;
      g.height = y + 1 - top;
      g.row0 = top;
      g.channels = plan.colour_channels;
      g.wrap_x = wrap_x;
      g.layers = window.layers();
      g.labels.resize(static_cast<std::size_t>(W) * g.height);
      if (y > 0) std::copy(previous[i].begin(), previous[i].end(), g.labels.begin());
      planes[i]->read_row(y, std::span<Label>(g.labels.data() + static_cast<std::size_t>(y - top) * W, W));
      sums[i] += grid_cost(g, y - top, g.height);
      std::copy(g.labels.end() - W, g.labels.end(), previous[i].begin());
    }
  }
  return sums;
}

SeamResult compute_graphcut_seams(const BlendPlan& plan, bool wrap_x, const std::filesystem::path& temp_dir,
                                  const std::function<void(double)>& progress, const GraphcutOptions& options) {
  const int W = plan.canvas.width, H = plan.canvas.height;
  auto part = [&](double from, double to) {
    return std::function<void(double)>([&progress, from, to](double f) {
      if (progress) progress(from + (to - from) * f);
    });
  };
  SeamResult depth = compute_seams(plan, wrap_x, temp_dir, part(0.0, 0.3), options.threads);
  const int k = options.scale > 0 ? options.scale : std::clamp(std::min(W, H) / 128, 1, 8);
  const CoarseGrid cg = coarse_layers(plan, k, part(0.3, 0.5));
  std::vector<unsigned char> band;
  SeamGrid coarse = coarse_labels(plan, cg, *depth.labels, wrap_x, band);
  expand_labels(coarse);
  mark_band(coarse, band);
  SeamResult result;
  result.labels = std::make_unique<LabelPlane>(temp_dir, W, H);
  Refinement(plan, coarse, band, k, *depth.labels, wrap_x).run(*result.labels, part(0.5, 0.8));
  const std::vector<double> costs = seam_costs(plan, {depth.labels.get(), result.labels.get()}, wrap_x);
  if (progress) progress(1.0);
  depth.depth_cost = costs[0];
  depth.cost = costs[0];
  if (costs[1] > costs[0]) return depth;
  result.overlaps = std::move(depth.overlaps);
  result.scratch_bytes = depth.scratch_bytes + result.labels->bytes();
  result.depth_cost = costs[0];
  result.cost = costs[1];
  return result;
}

}  // namespace gdp::blending
