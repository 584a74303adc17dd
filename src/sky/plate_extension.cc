// Plate extensions: the compact sources on the border ring bridged over, and Plate::extended.
#include "sky/plate_extension.h"

#include <algorithm>
#include <cmath>

#include "sky/seams.h"

namespace gdp::sky {
namespace {

constexpr int kWiden = 2;         // pixels added on each side of a source's run

// The border ring: 2 (w - 1) + 2 (h - 1) pixels, clockwise from (0, 0) (rows top down).
int ring_length(int w, int h) { return 2 * (w - 1) + 2 * (h - 1); }

// Ring index of border pixel (x, y).
int ring_index(int x, int y, int w, int h) {
  if (y == 0) return x;
  if (x == w - 1) return (w - 1) + y;
  if (y == h - 1) return (w - 1) + (h - 1) + (w - 1 - x);
  return (2 * (w - 1) + (h - 1) + (h - 1 - y)) % ring_length(w, h);
}

// The border pixel at ring index k.
void ring_pixel(int k, int w, int h, int& x, int& y) {
  if (k < w - 1) x = k, y = 0;
  else if (k < (w - 1) + (h - 1)) x = w - 1, y = k - (w - 1);
  else if (k < 2 * (w - 1) + (h - 1)) x = (w - 1) - (k - (w - 1) - (h - 1)), y = h - 1;
  else x = 0, y = (h - 1) - (k - 2 * (w - 1) - (h - 1));
}

// The correction at a point outside the plate: at the nearest border pixel, linear along the side.
float correction_at(const Plate& p, double x, double y) {
  const int w = p.width, h = p.height;
  const bool out_x = x < 0.0 || x > w, out_y = y < 0.0 || y > h;
  const auto at = [&](int i, int j) { return p.edge_correction[ring_index(i, j, w, h)]; };
  const auto along = [&](double t, int n, auto get) {  // t in pixel coordinates along a side of n pixels
    const double f = std::clamp(t - 0.5, 0.0, n - 1.0);
    const int i0 = static_cast<int>(f), i1 = std::min(i0 + 1, n - 1);
    return static_cast<float>(get(i0) + (f - i0) * (get(i1) - get(i0)));
  };
  if (out_x && out_y) return at(x < 0.0 ? 0 : w - 1, y < 0.0 ? 0 : h - 1);
  if (out_y) return along(x, w, [&](int i) { return at(i, y < 0.0 ? 0 : h - 1); });
  return along(y, h, [&](int j) { return at(x < 0.0 ? 0 : w - 1, j); });
}

}  // namespace

std::vector<float> edge_corrections(const Plate& plate, const std::vector<PlateSource>& sources) {
  const int w = plate.width, h = plate.height;
  if (w < 2 || h < 2) return {};
  const int n = ring_length(w, h);
  std::vector<float> ring(n);
  for (int k = 0; k < n; ++k) {
    int x = 0, y = 0;
    ring_pixel(k, w, h, x, y);
    ring[k] = plate.pixels[static_cast<std::size_t>(y) * w + x];
  }
  // The border pixels that compact sources cut by the edge cover: within a source's radius of its
  // peak (seam_sources.h's detection), and kWiden pixels more (the profile's wings).
  std::vector<float> correction(n, 0.0f);
  std::vector<char> source(n, 0);
  bool any = false;
  for (const PlateSource& c : sources) {
    const double reach = c.radius + kWiden;
    if (depth_inside(c.x + 0.5, c.y + 0.5, w, h) > reach) continue;
    for (int k = 0; k < n; ++k) {
      int x = 0, y = 0;
      ring_pixel(k, w, h, x, y);
      if (std::hypot(x - c.x, y - c.y) <= reach) source[k] = 1, any = true;
    }
  }
  if (!any) return correction;
  // Across each run of source pixels, the straight line between the finite pixels that bound it:
  // one walk around the ring from a pixel that is neither, offsets counted from there.
  const auto at = [n](int offset) { return offset % n; };
  const auto bounds = [&](int k) { return !source[k] && std::isfinite(ring[k]); };
  int start = 0;
  while (start < n && !bounds(start)) ++start;
  if (start == n) return correction;  // nothing but sources: leave the edge as it is
  for (int before = 0, after = 1; after <= n; ++after) {
    const int k = at(start + after);
    if (!bounds(k)) continue;
    const double a = ring[at(start + before)], b = ring[k];
    for (int j = before + 1; j < after; ++j) {
      const int i = at(start + j);
      if (std::isfinite(ring[i])) correction[i] = static_cast<float>(a + (b - a) * (j - before) / (after - before) - ring[i]);
    }
    before = after;
  }
  return correction;
}

float Plate::extended(double x, double y, double margin) const {
  const float edge = sample(x, y);
  const double outside = -std::min({x, width - x, y, height - y});
  if (outside <= 0.0 || !std::isfinite(edge)) return edge;
  // From the edge, less the sources found on it (a star cut by the edge is not drawn out along the extension).
  const float from = edge_correction.empty() ? edge : edge + correction_at(*this, x, y);
  const double t = std::min(1.0, outside / (0.8 * margin));
  const double s = t * t * (3.0 - 2.0 * t);
  return static_cast<float>(from * (1.0 - s) + fade_to * s);
}

}  // namespace gdp::sky
