// Interpolation among finite pixel centres: Catmull-Rom cubic where its 4 x 4 are finite, else bilinear among the finite ones.
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

// Catmull-Rom weights of the taps at -1, 0, 1, 2 for a point t in [0, 1) past tap 0.
inline void catmull_rom_weights(double t, double w[4]) {
  const double t2 = t * t, t3 = t2 * t;
  w[0] = 0.5 * (-t3 + 2.0 * t2 - t);
  w[1] = 0.5 * (3.0 * t3 - 5.0 * t2 + 2.0);
  w[2] = 0.5 * (-3.0 * t3 + 4.0 * t2 + t);
  w[3] = 0.5 * (t3 - t2);
}

// Catmull-Rom (the interpolating cubic: exact on quadratics, continuous gradient; half the
// smoothing of bilinear on a real sky map, docs/sky.md) when the 4 x 4 pixels around (x, y) are
// finite; else bilinear_finite, so blanks and edges cost no more than bilinear's.
template <class Fetch>
float interpolate_finite(double x, double y, Fetch&& fetch) {
  const double fx = x - 0.5, fy = y - 0.5;
  const int x0 = static_cast<int>(std::floor(fx)), y0 = static_cast<int>(std::floor(fy));
  double wx[4], wy[4];
  catmull_rom_weights(fx - x0, wx);
  catmull_rom_weights(fy - y0, wy);
  double sum = 0.0;
  for (int dy = 0; dy < 4; ++dy) {
    double row = 0.0;
    for (int dx = 0; dx < 4; ++dx) {
      const float v = fetch(x0 + dx - 1, y0 + dy - 1);
      if (!std::isfinite(v)) return bilinear_finite(x, y, fetch);
      row += wx[dx] * v;
    }
    sum += wy[dy] * row;
  }
  return static_cast<float>(sum);
}

// interpolate_finite on a row-major `width` x `height` grid of values, indices clamped to its edges.
inline float interpolate_clamped(const float* data, int width, int height, double x, double y) {
  return interpolate_finite(x, y, [&](int i, int j) {
    return data[static_cast<std::size_t>(std::clamp(j, 0, height - 1)) * width + std::clamp(i, 0, width - 1)];
  });
}

// bilinear_finite on such a grid: whether a point has a finite value, cheaply (NaN or not).
inline float bilinear_clamped(const float* data, int width, int height, double x, double y) {
  return bilinear_finite(x, y, [&](int i, int j) {
    return data[static_cast<std::size_t>(std::clamp(j, 0, height - 1)) * width + std::clamp(i, 0, width - 1)];
  });
}

}  // namespace gdp::sky
