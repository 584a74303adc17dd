// Row windows for tone mapping: a ring of recent rows and the rows beyond the ends, by the index map.
#include "apps/tonemap_window.h"

#include <algorithm>
#include <stdexcept>

namespace gdp::apps::tonemap {

RowWindow::RowWindow(Domain domain, int width, int height, int keep)
    : topology_(topology::make_topology(domain)), width_(width), height_(height), keep_(keep),
      ring_(keep, std::vector<float>(width)) {
  for (auto& g : ghosts_) g.resize(width);
}

void RowWindow::push(std::span<const float> row) {
  if (pushed_ >= height_) throw std::logic_error("RowWindow: more rows than the level has");
  std::copy(row.begin(), row.begin() + width_, ring_[pushed_ % keep_].begin());
  ++pushed_;
}

std::span<const float> RowWindow::held(int y) const {
  if (y < 0 || y >= pushed_ || y < pushed_ - keep_) throw std::logic_error("RowWindow: row not held");
  return ring_[y % keep_];
}

std::span<const float> RowWindow::row(int y) {
  if (y >= 0 && y < height_) return held(y);
  const std::span<const float> source = held(topology_->map(0, y, width_, height_).second);
  std::vector<float>& g = ghosts_[next_ghost_];
  next_ghost_ = (next_ghost_ + 1) % 4;
  for (int i = 0; i < width_; ++i) g[i] = source[topology_->map(i, y, width_, height_).first];
  return g;
}

}  // namespace gdp::apps::tonemap
