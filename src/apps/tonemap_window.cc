// Row windows for tone mapping: a ring of recent rows and the reflected or folded rows beyond the ends.
#include "apps/tonemap_window.h"

#include <algorithm>
#include <stdexcept>

namespace gdp::apps::tonemap {

int column(int i, int w, Domain domain) {
  if (domain != Domain::Planar) return ((i % w) + w) % w;
  if (i < 0) i = -1 - i;
  if (i >= w) i = 2 * w - 1 - i;
  return std::clamp(i, 0, w - 1);
}

RowWindow::RowWindow(Domain domain, int width, int height, int keep)
    : domain_(domain), width_(width), height_(height), keep_(keep), ring_(keep, std::vector<float>(width)) {
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
  const bool top = y < 0;
  const int source = std::clamp(top ? -1 - y : 2 * height_ - 1 - y, 0, height_ - 1);
  const std::span<const float> r = held(source);
  if (domain_ != Domain::Spherical) return r;
  std::vector<float>& g = ghosts_[next_ghost_];
  next_ghost_ = (next_ghost_ + 1) % 4;
  const int w = width_;
  for (int i = 0; i < w; ++i) g[i] = r[top ? w - 1 - i : ((w / 2 - 1 - i) % w + w) % w];
  return g;
}

}  // namespace gdp::apps::tonemap
