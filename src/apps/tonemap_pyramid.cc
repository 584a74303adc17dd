// The log-luminance pyramid, streamed: each level reduces its rows into the next as they arrive.
#include "apps/tonemap_pyramid.h"

#include <fmt/format.h>

#include <algorithm>

#include "apps/tonemap_colour.h"
#include "apps/tonemap_filters.h"
#include "apps/tonemap_window.h"

namespace gdp::apps::tonemap {
namespace {

// One level of the cascade: takes its rows in order, sums gradient magnitudes, stores them
// (levels >= 1) and hands each row of the next level on as soon as its fine rows are in.
class LevelStream {
 public:
  LevelStream(Domain domain, int width, int height, schedule::RowStore<float>* store, LevelStream* next)
      : window_(domain, width, height, 4), store_(store), next_(next), g_(width),
        coarse_(next ? next->window_.width() : 0) {}

  void push(std::span<const float> row) {
    if (store_) store_->append(row);
    window_.push(row);
    const int y = window_.pushed() - 1;
    if (y >= 1) add_gradient(y - 1);
    if (next_ && y >= 2 && y % 2 == 0) emit((y - 2) / 2);
  }

  void finish() {
    add_gradient(window_.height() - 1);
    if (next_) {
      for (int r = emitted_; r < next_->window_.height(); ++r) emit(r);
      next_->finish();
    }
  }

  double mean_gradient() const { return sum_ / (double(window_.width()) * window_.height()); }

 private:
  void add_gradient(int y) {
    gradient_magnitude(window_, y, g_);
    double s = 0.0;
    for (float v : g_) s += v;
    sum_ += s;
  }
  void emit(int r) {
    reduce_row(window_, r, coarse_);
    next_->push(coarse_);
    emitted_ = r + 1;
  }

  RowWindow window_;
  schedule::RowStore<float>* store_;
  LevelStream* next_;
  std::vector<float> g_, coarse_;
  double sum_ = 0.0;
  int emitted_ = 0;
};

}  // namespace

int pyramid_levels(int width, int height, int requested) {
  int levels = 1;
  const auto deeper = [&] {
    if (requested > 0) return levels < requested && std::min(width, height) > 1;
    return std::min(coarser(width), coarser(height)) >= 32;
  };
  while (deeper()) {
    width = coarser(width);
    height = coarser(height);
    ++levels;
  }
  return levels;
}

Pyramid build_pyramid(RowReader& in, Domain domain, int levels, const schedule::StorePolicy& policy) {
  Pyramid p;
  p.levels = levels;
  int w = in.width(), h = in.height();
  for (int k = 0; k < levels; ++k) {
    p.widths.push_back(w);
    p.heights.push_back(h);
    p.rows.push_back(k == 0 ? nullptr
                            : std::make_unique<schedule::RowStore<float>>(policy, w, h, fmt::format("tonemap-level{}", k)));
    w = coarser(w);
    h = coarser(h);
  }
  std::vector<std::unique_ptr<LevelStream>> streams(levels);
  for (int k = levels - 1; k >= 0; --k)
    streams[k] = std::make_unique<LevelStream>(domain, p.widths[k], p.heights[k], p.rows[k].get(),
                                               k + 1 < levels ? streams[k + 1].get() : nullptr);
  std::vector<float> row(static_cast<std::size_t>(in.channels()) * in.width()), log_l(in.width());
  for (int y = 0; y < in.height(); ++y) {
    in.read_row(y, row);
    log_luminance(row, in.width(), in.channels(), log_l);
    streams[0]->push(log_l);
  }
  streams[0]->finish();
  for (const auto& s : streams) p.mean_gradient.push_back(s->mean_gradient());
  return p;
}

}  // namespace gdp::apps::tonemap
