// HiPS pyramid: deepest tiles in nested order, parents accumulated from their children as they pass.
#include "sky/hips_pyramid.h"

#include <cmath>
#include <limits>

namespace gdp::sky {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// One pending parent per order: sums and counts of its children's finite pixels.
struct Pending {
  std::int64_t npix = -1;
  bool any = false;
  std::vector<float> sum;
  std::vector<float> count;
};

// Adds child `child` (2x2 means) into its parent's quadrant.
void add_child(Pending& p, std::int64_t child, const Image& tile) {
  const int w = tile.width, half = w / 2;
  const int r0 = static_cast<int>(child & 1) * half, c0 = static_cast<int>((child >> 1) & 1) * half;
  for (int r = 0; r < half; ++r)
    for (int c = 0; c < half; ++c) {
      float s = 0.0f, n = 0.0f;
      for (int dr = 0; dr < 2; ++dr)
        for (int dc = 0; dc < 2; ++dc) {
          const float v = tile.at(0, 2 * c + dc, 2 * r + dr);
          if (std::isfinite(v)) s += v, n += 1.0f;
        }
      const std::size_t k = static_cast<std::size_t>(r0 + r) * w + c0 + c;
      p.sum[k] = s;
      p.count[k] = n;
      if (n > 0.0f) p.any = true;
    }
}

class Pyramid {
 public:
  Pyramid(int order, int min_order, int width, const HipsEmit& emit)
      : order_(order), min_order_(min_order), width_(width), emit_(emit), pending_(order + 1) {}

  // A tile of `order` with data: emitted, then handed to its parent.
  void tile_done(int order, std::int64_t npix, const Image& tile) {
    emit_(order, npix, tile);
    if (order <= min_order_) return;
    Pending& p = pending_[order - 1];
    if (p.npix != (npix >> 2)) {
      flush(order - 1);
      start(p, npix >> 2);
    }
    add_child(p, npix & 3, tile);
  }

  // Finishes every pending parent, deepest first.
  void finish() {
    for (int k = order_ - 1; k >= min_order_; --k) flush(k);
  }

 private:
  void start(Pending& p, std::int64_t npix) {
    const std::size_t n = static_cast<std::size_t>(width_) * width_;
    p.npix = npix;
    p.any = false;
    p.sum.assign(n, 0.0f);
    p.count.assign(n, 0.0f);
  }

  void flush(int order) {
    Pending& p = pending_[order];
    if (p.npix < 0) return;
    const std::int64_t npix = p.npix;
    p.npix = -1;
    if (!p.any) return;
    Image tile(width_, width_, 1);
    for (std::size_t k = 0; k < tile.data.size(); ++k) tile.data[k] = p.count[k] > 0.0f ? p.sum[k] / p.count[k] : kNaN;
    tile_done(order, npix, tile);
  }

  int order_, min_order_, width_;
  const HipsEmit& emit_;
  std::vector<Pending> pending_;
};

}  // namespace

void build_hips_pyramid(int order, int min_order, int width, const std::vector<std::int64_t>& deepest,
                        const HipsSample& sample, const HipsEmit& emit) {
  Pyramid pyramid(order, min_order, width, emit);
  Image tile(width, width, 1);
  for (const std::int64_t npix : deepest) {
    std::fill(tile.data.begin(), tile.data.end(), kNaN);
    if (sample(npix, tile)) pyramid.tile_done(order, npix, tile);
  }
  pyramid.finish();
}

}  // namespace gdp::sky
