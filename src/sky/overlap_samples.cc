// Sample points two plates share: a's grid points mapped through the sky into b, and the values' difference.
#include "sky/overlap_samples.h"

#include <algorithm>
#include <cmath>

#include "sphere/vec3.h"

namespace gdp::sky {

bool cones_meet(const Plate& a, const Plate& b) {
  const double reach = std::acos(std::clamp(a.cos_radius, -1.0, 1.0)) + std::acos(std::clamp(b.cos_radius, -1.0, 1.0));
  return sphere::angle(a.centre, b.centre) <= reach;
}

namespace {
int grid_stride(const Plate& a) { return std::max(1, std::max(a.width, a.height) / 64); }
}  // namespace

std::size_t overlap_sample_bound(const Plate& a) {
  const std::size_t s = grid_stride(a);
  return ((a.width + s - 1) / s) * ((a.height + s - 1) / s);
}

std::vector<OverlapSample> overlap_samples(const Plate& a, const Plate& b) {
  const int stride = grid_stride(a);
  std::vector<double> xy, sky, bxy;
  std::vector<unsigned char> ok, bok;
  std::vector<float> values;
  for (int y = 0; y < a.height; y += stride)
    for (int x = 0; x < a.width; x += stride) {
      const float v = a.pixels[static_cast<std::size_t>(y) * a.width + x];
      if (!std::isfinite(v)) continue;
      xy.push_back(x + 0.5);
      xy.push_back(y + 0.5);
      values.push_back(v);
    }
  const std::size_t n = values.size();
  sky.resize(2 * n);
  bxy.resize(2 * n);
  ok.resize(n);
  bok.resize(n);
  a.wcs->pixel_to_sky(xy, sky, ok);
  b.wcs->sky_to_pixel(sky, bxy, bok);
  std::vector<OverlapSample> samples;
  for (std::size_t k = 0; k < n; ++k) {
    const double x = bxy[2 * k], y = bxy[2 * k + 1];
    if (!ok[k] || !bok[k] || x < 0.0 || y < 0.0 || x >= b.width || y >= b.height) continue;
    const float w = b.sample(x, y);
    if (!std::isfinite(w)) continue;
    samples.push_back({xy[2 * k], xy[2 * k + 1], x, y, double(values[k]) - w});
  }
  return samples;
}

}  // namespace gdp::sky
