// TOAST tiles of a sky mosaic: percentile stretch of the covered pixels, alpha = coverage, gdp's TOAST writer.
#include "sky/toast_output.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "gdp/sphere.h"

namespace gdp::sky {

int toast_height(int height) {
  int h = 128;
  while (h < height) h *= 2;
  return h;
}

void write_sky_toast(const PqStore& store, const std::filesystem::path& dir) {
  const auto [lo, hi] = display_range(store);
  const Image pq = store.whole();  // the pyramid writer takes one image (docs/sky.md, "Memory")
  Image tiles(pq.width, pq.height, 2);
  for (std::size_t k = 0; k < pq.plane_size(); ++k) {
    const float v = pq.data[k];
    const bool covered = std::isfinite(v);
    tiles.data[k] = covered ? std::clamp((v - lo) / (hi - lo), 0.0f, 1.0f) : 0.0f;
    tiles.data[pq.plane_size() + k] = covered ? 1.0f : 0.0f;
  }
  sphere::ToastPyramidOptions options;
  options.name = "gdp sky";
  sphere::write_toast_pyramid(tiles, dir, options);
}

}  // namespace gdp::sky
