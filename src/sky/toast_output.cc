// TOAST tiles of a sky mosaic: percentile stretch of the covered pixels, alpha = coverage, gdp's TOAST writer fed PQ rows from the store.
#include "sky/toast_output.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "gdp/errors.h"
#include "gdp/sphere.h"

namespace gdp::sky {

int toast_height(int height) {
  int h = 128;
  while (h < height) h *= 2;
  return h;
}

void write_sky_toast(const PqStore& store, const std::filesystem::path& dir) {
  const auto [lo, hi] = display_range(store);
  const int h = store.window().height, n = 2 * h;
  if (!store.window().whole()) throw UsageError("TOAST output needs the whole PQ sphere, not a window of it");
  std::vector<float> pq(static_cast<std::size_t>(4) * h);
  const auto square_row = [&](int y, std::span<float> row) {  // grey, then alpha
    store.read_row(sphere::square_row_source(h, y), pq);
    sphere::square_row_from_pq(h, y, pq, row.first(n));
    for (int x = 0; x < n; ++x) {
      const float v = row[x];
      const bool covered = std::isfinite(v);
      row[x] = covered ? std::clamp((v - lo) / (hi - lo), 0.0f, 1.0f) : 0.0f;
      row[n + x] = covered ? 1.0f : 0.0f;
    }
  };
  sphere::ToastPyramidOptions options;
  options.name = "gdp sky";
  sphere::write_toast_pyramid(h, 2, square_row, dir, options);
}

}  // namespace gdp::sky
