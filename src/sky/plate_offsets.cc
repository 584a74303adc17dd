// Plate offsets from overlaps: mean differences on sample points, then Gauss-Seidel on the overlap graph.
#include "sky/plate_offsets.h"

#include <algorithm>
#include <cmath>

#include "sphere/vec3.h"

namespace gdp::sky {
namespace {

struct Overlap {
  double sum = 0.0;  // of (a - b)
  long long n = 0;
};

// Mean difference of plate a minus plate b over a's sample points inside b.
Overlap overlap(const Plate& a, const Plate& b) {
  Overlap o;
  const int stride = std::max(1, std::max(a.width, a.height) / 64);
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
  for (std::size_t k = 0; k < n; ++k) {
    const double x = bxy[2 * k], y = bxy[2 * k + 1];
    if (!ok[k] || !bok[k] || x < 0.0 || y < 0.0 || x >= b.width || y >= b.height) continue;
    const float w = b.sample(x, y);
    if (!std::isfinite(w)) continue;
    o.sum += double(values[k]) - w;
    ++o.n;
  }
  return o;
}

}  // namespace

std::vector<double> plate_offsets(const std::vector<Plate>& plates) {
  const std::size_t m = plates.size();
  std::vector<Overlap> pairs(m * m);
  for (std::size_t a = 0; a < m; ++a)
    for (std::size_t b = a + 1; b < m; ++b) {
      const double reach = std::acos(std::clamp(plates[a].cos_radius, -1.0, 1.0)) +
                           std::acos(std::clamp(plates[b].cos_radius, -1.0, 1.0));
      if (sphere::angle(plates[a].centre, plates[b].centre) > reach) continue;
      pairs[a * m + b] = overlap(plates[a], plates[b]);
      pairs[b * m + a] = {-pairs[a * m + b].sum, pairs[a * m + b].n};
    }
  std::vector<double> o(m, 0.0);
  std::vector<unsigned char> linked(m, 0);
  for (int sweep = 0; sweep < 1000; ++sweep) {
    double change = 0.0;
    for (std::size_t a = 0; a < m; ++a) {
      double num = 0.0, den = 0.0;
      for (std::size_t b = 0; b < m; ++b) {
        const Overlap& p = pairs[a * m + b];
        if (p.n == 0) continue;
        num += p.n * o[b] + p.sum;  // n (o_b + mean(a - b))
        den += static_cast<double>(p.n);
      }
      if (den == 0.0) continue;
      linked[a] = 1;
      change = std::max(change, std::abs(num / den - o[a]));
      o[a] = num / den;
    }
    if (change < 1e-12) break;
  }
  double mean = 0.0;
  long long count = 0;
  for (std::size_t a = 0; a < m; ++a)
    if (linked[a]) {
      mean += o[a];
      ++count;
    }
  if (count) mean /= static_cast<double>(count);
  for (std::size_t a = 0; a < m; ++a) o[a] = linked[a] ? o[a] - mean : 0.0;
  return o;
}

void set_fade_levels(std::vector<Plate>& plates) {
  const std::vector<double> o = plate_offsets(plates);
  double level = 0.0;
  for (std::size_t k = 0; k < plates.size(); ++k) level += plates[k].mean - o[k];
  level /= static_cast<double>(plates.size());
  for (std::size_t k = 0; k < plates.size(); ++k) plates[k].fade_to = level + o[k];
}

}  // namespace gdp::sky
