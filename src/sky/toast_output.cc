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

std::pair<float, float> display_range(const Image& pq) {
  // Percentiles from at most about a million covered samples.
  const std::size_t stride = std::max<std::size_t>(1, pq.data.size() / (std::size_t{1} << 20));
  std::vector<float> sample;
  for (std::size_t k = 0; k < pq.data.size(); k += stride)
    if (std::isfinite(pq.data[k])) sample.push_back(pq.data[k]);
  float lo = 0.0f, hi = 1.0f;
  if (!sample.empty()) {
    const auto at = [&](double q) {
      auto it = sample.begin() + static_cast<std::ptrdiff_t>(q * (sample.size() - 1));
      std::nth_element(sample.begin(), it, sample.end());
      return *it;
    };
    lo = at(0.005);
    hi = at(0.995);
    if (!(hi > lo)) hi = lo + 1.0f;
  }
  return {lo, hi};
}

void write_sky_toast(const Image& pq, const std::filesystem::path& dir) {
  const auto [lo, hi] = display_range(pq);
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
