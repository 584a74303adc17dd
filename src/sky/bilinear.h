// Bilinear interpolation among the finite ones of the four pixel centres around a point (blanks left out).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

namespace gdp::sky {

// (x, y) in pixel coordinates (pixel (i, j) covers [i, i + 1) x [j, j + 1)); fetch(i, j) gives
// a pixel's value (the caller clamps or wraps the indices). NaN when none of the four is finite.
template <class Fetch>
float bilinear_finite(double x, double y, Fetch&& fetch) {
  const double fx = x - 0.5, fy = y - 0.5;
  const int x0 = static_cast<int>(std::floor(fx)), y0 = static_cast<int>(std::floor(fy));
  const double ax = fx - x0, ay = fy - y0;
  double sum = 0.0, weight = 0.0;
  for (int dy = 0; dy < 2; ++dy)
    for (int dx = 0; dx < 2; ++dx) {
      const float v = fetch(x0 + dx, y0 + dy);
      const double w = (dx ? ax : 1.0 - ax) * (dy ? ay : 1.0 - ay);
      if (!std::isfinite(v) || w == 0.0) continue;
      sum += w * v;
      weight += w;
    }
  return weight > 0.0 ? static_cast<float>(sum / weight) : std::numeric_limits<float>::quiet_NaN();
}

// bilinear_finite on a row-major `width` x `height` grid of values, indices clamped to its edges.
inline float bilinear_clamped(const float* data, int width, int height, double x, double y) {
  return bilinear_finite(x, y, [&](int i, int j) {
    return data[static_cast<std::size_t>(std::clamp(j, 0, height - 1)) * width + std::clamp(i, 0, width - 1)];
  });
}

}  // namespace gdp::sky
