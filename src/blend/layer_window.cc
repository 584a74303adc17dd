// The layers crossing a band of canvas rows, read row by row as the band slides down the canvas.
#include "blend/layer_window.h"

#include <algorithm>
#include <numeric>

namespace gdp::blending {

struct LayerWindow::Open {
  int index;
  Patch patch;
  std::unique_ptr<LayerRows> rows;  // null after its last row
  std::vector<float> colour;
  std::vector<unsigned char> covered;
};

LayerWindow::LayerWindow(const BlendPlan& plan)
    : plan_(plan), where_(plan.layers.size()), by_top_(plan.layers.size()), by_layer_(plan.layers.size(), nullptr) {
  for (std::size_t k = 0; k < where_.size(); ++k) where_[k] = footprint(plan, static_cast<int>(k));
  std::iota(by_top_.begin(), by_top_.end(), 0);
  std::stable_sort(by_top_.begin(), by_top_.end(), [&](int a, int b) { return where_[a].y0 < where_[b].y0; });
}

LayerWindow::~LayerWindow() = default;

void LayerWindow::read_row(int y) {
  for (; next_ < by_top_.size() && where_[by_top_[next_]].y0 <= y; ++next_) {
    const int k = by_top_[next_];
    if (where_[k].y1 <= y || where_[k].width() <= 0) continue;
    auto o = std::make_unique<Open>();
    o->index = k;
    o->patch.x0 = where_[k].x0;
    o->patch.w = where_[k].width();
    o->patch.y0 = y;
    o->rows = std::make_unique<LayerRows>(plan_, k, 0, plan_.canvas.width, open_.size() < 8);
    o->colour.resize(static_cast<std::size_t>(plan_.colour_channels) * o->patch.w);
    o->covered.resize(o->patch.w);
    by_layer_[k] = &o->patch;
    open_.push_back(std::move(o));
  }
  const int c = plan_.colour_channels;
  for (auto& o : open_) {
    if (!o->rows) continue;
    const int w = o->patch.w;
    o->rows->read(y, o->colour, o->covered);
    Patch& p = o->patch;
    const std::size_t at = p.colour.size();
    p.colour.resize(at + static_cast<std::size_t>(c) * w);
    for (int x = 0; x < w; ++x)
      for (int ch = 0; ch < c; ++ch) p.colour[at + static_cast<std::size_t>(x) * c + ch] = o->colour[static_cast<std::size_t>(ch) * w + x];
    p.covers.insert(p.covers.end(), o->covered.begin(), o->covered.end());
    ++p.h;
    if (y + 1 == where_[o->index].y1) o->rows.reset();
  }
}

void LayerWindow::slide(int top, int bottom) {
  for (int y = std::max(bottom_, top); y < bottom; ++y) read_row(y);
  bottom_ = std::max(bottom_, bottom);
  top_ = std::max(top_, top);
  const int c = plan_.colour_channels;
  for (auto& o : open_) {
    Patch& p = o->patch;
    const int drop = std::clamp(top_ - p.y0, 0, p.h);
    if (drop == 0) continue;
    p.colour.erase(p.colour.begin(), p.colour.begin() + static_cast<std::ptrdiff_t>(drop) * p.w * c);
    p.covers.erase(p.covers.begin(), p.covers.begin() + static_cast<std::ptrdiff_t>(drop) * p.w);
    p.y0 += drop;
    p.h -= drop;
  }
  std::erase_if(open_, [&](const auto& o) {
    const bool done = !o->rows && o->patch.h == 0;
    if (done) by_layer_[o->index] = nullptr;
    return done;
  });
}

}  // namespace gdp::blending
