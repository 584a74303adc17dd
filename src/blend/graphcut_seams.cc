// Graph-cut seams: alpha-expansion on a coarse grid of the layers, then at full resolution around the coarse seams.
#include "blend/graphcut_seams.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "blend/layer_window.h"

namespace gdp::blending {
namespace {

// gdp blend's canvas as the graph cut's layers: a LayerWindow per pass. The cost of an uncovered
// cell is the sum over channels of the largest difference of values, at least 1 (values in [0, 1]
// give `channels`; FITS data in other units, gdp sky --projected, their own range).
class CanvasLayers final : public SeamLayers {
 public:
  explicit CanvasLayers(const BlendPlan& plan)
      : plan_(plan), lo_(plan.colour_channels, 0.0f), hi_(plan.colour_channels, 1.0f) {}
  int width() const override { return plan_.canvas.width; }
  int height() const override { return plan_.canvas.height; }
  int channels() const override { return plan_.colour_channels; }
  void restart() override {
    window_ = std::make_unique<LayerWindow>(plan_);
    seen_ = 0;
  }
  void slide(int top, int bottom) override {
    window_->slide(top, bottom);
    for (int y = std::max(seen_, top); y < bottom; ++y) widen_range(y);
    seen_ = std::max(seen_, bottom);
  }
  const std::vector<const Patch*>& layers() const override { return window_->layers(); }
  double uncovered_cost() const override {
    double sum = 0;
    for (std::size_t c = 0; c < lo_.size(); ++c) sum += std::max(1.0, static_cast<double>(hi_[c]) - lo_[c]);
    return sum;
  }

 private:
  void widen_range(int y) {
    const int c = plan_.colour_channels;
    for (const Patch* p : window_->layers()) {
      if (!p || y < p->y0 || y >= p->y0 + p->h) continue;
      for (int x = p->x0; x < p->x0 + p->w; ++x)
        for (int ch = 0; ch < c && p->has(x, y); ++ch) {
          const float v = p->at(x, y, c)[ch];
          lo_[ch] = std::min(lo_[ch], v);
          hi_[ch] = std::max(hi_[ch], v);
        }
    }
  }
  const BlendPlan& plan_;
  std::unique_ptr<LayerWindow> window_;
  int seen_ = 0;                // rows whose values widened the range this pass
  std::vector<float> lo_, hi_;  // the values seen (every pass), starting from [0, 1]
};

// The layers on a grid of k x k cells: each layer's mean colour per cell, `covers` where it
// covers the whole cell. Memory: (4 x channels + 5) bytes per cell of each layer.
struct CoarseGrid {
  int k = 1, width = 0, height = 0;
  std::vector<Patch> patches;
};

// One layer's cells while the coarse pass reads it: per coarse row, a span of cells with the sums
// of its colour and its pixel counts there, grown as its rows arrive (no footprint needed).
struct CellRows {
  struct Row {
    int x0 = 0;
    std::vector<float> sum;
    std::vector<int> count;
  };
  int y0 = -1;
  std::vector<Row> rows;

  // Coarse row cy, spanning at least cells [a, b).
  Row& span(int cy, int a, int b, int c) {
    if (y0 < 0) y0 = cy;
    if (static_cast<int>(rows.size()) <= cy - y0) rows.resize(cy - y0 + 1);
    Row& r = rows[cy - y0];
    const int end = r.x0 + static_cast<int>(r.count.size());
    if (!r.count.empty() && a >= r.x0 && b <= end) return r;
    const int x0 = r.count.empty() ? a : std::min(a, r.x0), x1 = r.count.empty() ? b : std::max(b, end);
    Row grown{x0, std::vector<float>(static_cast<std::size_t>(x1 - x0) * c, 0.0f), std::vector<int>(x1 - x0, 0)};
    std::copy(r.sum.begin(), r.sum.end(), grown.sum.begin() + static_cast<std::ptrdiff_t>(r.x0 - x0) * c);
    std::copy(r.count.begin(), r.count.end(), grown.count.begin() + (r.x0 - x0));
    r = std::move(grown);
    return r;
  }

  // The cells as a Patch: mean colours, `covers` where the count fills the cell (of k x k pixels
  // clipped to W x H).
  Patch patch(int k, int W, int H, int c) {
    Patch p;
    int x1 = 0;
    p.x0 = W;
    for (const Row& r : rows)
      if (!r.count.empty()) {
        p.x0 = std::min(p.x0, r.x0);
        x1 = std::max(x1, r.x0 + static_cast<int>(r.count.size()));
      }
    if (x1 <= p.x0) return {};
    p.y0 = y0;
    p.w = x1 - p.x0;
    p.h = static_cast<int>(rows.size());
    p.colour.assign(static_cast<std::size_t>(p.w) * p.h * c, 0.0f);
    p.covers.assign(static_cast<std::size_t>(p.w) * p.h, 0);
    for (int cy = p.y0; cy < p.y0 + p.h; ++cy) {
      Row& r = rows[cy - y0];
      for (std::size_t i = 0; i < r.count.size(); ++i) {
        const int cx = r.x0 + static_cast<int>(i), count = r.count[i];
        const std::size_t cell = static_cast<std::size_t>(cy - p.y0) * p.w + (cx - p.x0);
        const int area = (std::min((cx + 1) * k, W) - cx * k) * (std::min((cy + 1) * k, H) - cy * k);
        p.covers[cell] = count == area;
        for (int ch = 0; ch < c && count > 0; ++ch)
          p.colour[cell * c + ch] = r.sum[i * c + ch] / static_cast<float>(count);
      }
      r = Row{};
    }
    return p;
  }
};

CoarseGrid coarse_layers(SeamLayers& layers, int k, const std::function<void(double)>& progress) {
  const int c = layers.channels(), W = layers.width(), H = layers.height();
  CoarseGrid g;
  g.k = k;
  g.width = (W + k - 1) / k;
  g.height = (H + k - 1) / k;
  layers.restart();
  std::vector<CellRows> cells;
  for (int y = 0; y < H; ++y) {
    layers.slide(y, y + 1);
    const std::vector<const Patch*>& rows = layers.layers();
    cells.resize(std::max(cells.size(), rows.size()));
    for (std::size_t l = 0; l < rows.size(); ++l) {
      const Patch* row = rows[l];
      if (!row || row->w <= 0 || y < row->y0 || y >= row->y0 + row->h) continue;
      CellRows::Row& r = cells[l].span(y / k, row->x0 / k, (row->x0 + row->w - 1) / k + 1, c);
      for (int x = row->x0; x < row->x0 + row->w; ++x) {
        if (!row->has(x, y)) continue;
        const std::size_t cell = x / k - r.x0;
        ++r.count[cell];
        const float* v = row->at(x, y, c);
        for (int ch = 0; ch < c; ++ch) r.sum[cell * c + ch] += v[ch];
      }
    }
    if (progress) progress(static_cast<double>(y + 1) / H);
  }
  for (CellRows& l : cells) g.patches.push_back(l.patch(k, W, H, c));
  return g;
}

// A grid of the layers' rows [top, end) at full resolution; its labels and free cells are the
// caller's to fill.
SeamGrid layer_rows(const SeamLayers& layers, int top, int end, bool wrap_x) {
  SeamGrid g;
  g.width = layers.width();
  g.height = end - top;
  g.row0 = top;
  g.channels = layers.channels();
  g.uncovered = layers.uncovered_cost();
  g.wrap_x = wrap_x;
  g.layers = layers.layers();
  return g;
}

// The coarse labels: the depth seams' label at each cell's centre where that layer covers the
// cell, else the first layer that does (else the depth label, fixed). Cells two or more layers
// cover are free; `band` marks cells no layer wholly covers (refined at full resolution).
SeamGrid coarse_labels(const SeamLayers& layers, const CoarseGrid& cg, const LabelPlane& depth, bool wrap_x,
                       std::vector<unsigned char>& band) {
  const int W = layers.width(), H = layers.height(), k = cg.k;
  SeamGrid g;
  g.width = cg.width;
  g.height = cg.height;
  g.channels = layers.channels();
  g.uncovered = layers.uncovered_cost();
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
  Refinement(SeamLayers& layers, const SeamGrid& coarse, const std::vector<unsigned char>& band, int k,
             const LabelPlane& depth, bool wrap_x)
      : layers_(layers), coarse_(coarse), band_(band), k_(k), depth_(depth), wrap_x_(wrap_x) {}

  // Writes the labels to `out`; returns the seam costs (grid_cost over the whole grid, strip by
  // strip with the layers held) of the depth labels and of those written.
  std::array<double, 2> run(LabelPlane& out, const std::function<void(double)>& progress) {
    const int H = layers_.height(), W = layers_.width();
    layers_.restart();
    const int strip = std::max(64, 4 * k_), lookahead = std::max(32, 2 * k_);
    std::vector<Label> above, depth;
    std::array<double, 2> costs{0.0, 0.0};
    for (int y0 = 0; y0 < H; y0 += strip) {
      const int y1 = std::min(H, y0 + strip), end = std::min(H, y1 + lookahead), top = y0 > 0 ? y0 - 1 : 0;
      layers_.slide(top, end);
      SeamGrid g = grid(top, end, y0, above);
      expand_labels(g);
      costs[1] += grid_cost(g, y0 - top, y1 - top);
      depth.resize(static_cast<std::size_t>(end - top) * W);
      for (int y = top; y < y1; ++y)
        depth_.read_row(y, std::span<Label>(depth).subspan(static_cast<std::size_t>(y - top) * W, W));
      std::swap(g.labels, depth);  // the depth labels on the same rows and layers
      costs[0] += grid_cost(g, y0 - top, y1 - top);
      std::swap(g.labels, depth);
      for (int y = y0; y < y1; ++y)
        out.write_row(y, std::span<const Label>(g.labels.data() + static_cast<std::size_t>(y - top) * W, W));
      above.assign(g.labels.begin() + static_cast<std::ptrdiff_t>(y1 - 1 - top) * W,
                   g.labels.begin() + static_cast<std::ptrdiff_t>(y1 - top) * W);
      if (progress) progress(static_cast<double>(y1) / H);
    }
    return costs;
  }

 private:
  // Rows [top, end): the row above y0 fixed at `above`; the others start from the coarse label
  // where that layer covers the pixel, else the depth label; free in the band where 2+ layers cover.
  SeamGrid grid(int top, int end, int y0, const std::vector<Label>& above) {
    const int W = layers_.width();
    SeamGrid g = layer_rows(layers_, top, end, wrap_x_);
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

  SeamLayers& layers_;
  const SeamGrid& coarse_;
  const std::vector<unsigned char>& band_;
  int k_;
  const LabelPlane& depth_;
  bool wrap_x_;
};

}  // namespace

std::vector<double> seam_costs(SeamLayers& layers, const std::vector<const LabelPlane*>& planes, bool wrap_x) {
  const int W = layers.width(), H = layers.height();
  std::vector<double> sums(planes.size(), 0.0);
  layers.restart();
  std::vector<std::vector<Label>> previous(planes.size(), std::vector<Label>(W));
  for (int y = 0; y < H; ++y) {
    const int top = std::max(0, y - 1);
    layers.slide(top, y + 1);
    for (std::size_t i = 0; i < planes.size(); ++i) {
      SeamGrid g = layer_rows(layers, top, y + 1, wrap_x);
      g.labels.resize(static_cast<std::size_t>(W) * g.height);
      if (y > 0) std::copy(previous[i].begin(), previous[i].end(), g.labels.begin());
      planes[i]->read_row(y, std::span<Label>(g.labels.data() + static_cast<std::size_t>(y - top) * W, W));
      sums[i] += grid_cost(g, y - top, g.height);
      std::copy(g.labels.end() - W, g.labels.end(), previous[i].begin());
    }
  }
  return sums;
}

std::vector<double> seam_costs(const BlendPlan& plan, const std::vector<const LabelPlane*>& planes, bool wrap_x) {
  CanvasLayers layers(plan);
  layers.restart();
  for (int y = 0; y < plan.canvas.height; ++y) layers.slide(y, y + 1);  // the values' range first
  return seam_costs(layers, planes, wrap_x);
}

GraphcutLabels graphcut_labels(SeamLayers& layers, const LabelPlane& depth, bool wrap_x,
                               const std::filesystem::path& temp_dir, const std::function<void(double)>& progress,
                               const GraphcutOptions& options) {
  const int W = layers.width(), H = layers.height();
  auto part = [&](double from, double to) {
    return std::function<void(double)>([&progress, from, to](double f) {
      if (progress) progress(from + (to - from) * f);
    });
  };
  const int k = options.scale > 0 ? options.scale : std::clamp(std::min(W, H) / 128, 1, 8);
  const CoarseGrid cg = coarse_layers(layers, k, part(0.0, 0.4));
  std::vector<unsigned char> band;
  SeamGrid coarse = coarse_labels(layers, cg, depth, wrap_x, band);
  expand_labels(coarse);
  mark_band(coarse, band);
  auto labels = std::make_unique<LabelPlane>(temp_dir, W, H);
  const std::array<double, 2> costs = Refinement(layers, coarse, band, k, depth, wrap_x).run(*labels, part(0.4, 1.0));
  if (progress) progress(1.0);
  GraphcutLabels out;
  out.depth_cost = costs[0];
  out.cost = std::min(costs[0], costs[1]);
  if (costs[1] <= costs[0]) out.labels = std::move(labels);
  return out;
}

SeamResult compute_graphcut_seams(const BlendPlan& plan, bool wrap_x, const std::filesystem::path& temp_dir,
                                  const std::function<void(double)>& progress, const GraphcutOptions& options) {
  SeamResult depth = compute_seams(plan, wrap_x, temp_dir, [&progress](double f) {
    if (progress) progress(0.3 * f);
  }, options.threads);
  CanvasLayers layers(plan);
  GraphcutLabels cut = graphcut_labels(layers, *depth.labels, wrap_x, temp_dir, [&progress](double f) {
    if (progress) progress(0.3 + 0.7 * f);
  }, options);
  depth.depth_cost = cut.depth_cost;
  depth.cost = cut.cost;
  if (!cut.labels) return depth;
  SeamResult result;
  result.labels = std::move(cut.labels);
  result.overlaps = std::move(depth.overlaps);
  result.scratch_bytes = depth.scratch_bytes + result.labels->bytes();
  result.depth_cost = cut.depth_cost;
  result.cost = cut.cost;
  return result;
}

}  // namespace gdp::blending
