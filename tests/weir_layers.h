// Test layers cut from a real photo: weir_1_crop.jpg as 3x2 overlapping layers with exposure offsets, gains and vignetting.
#pragma once

#include <utility>
#include <vector>

#include "gdp/blend.h"
#include "gdp/image_io.h"

namespace gdp::test {

struct WeirLayers {
  Image photo;
  std::vector<Image> layers;
  std::vector<ImageLayer> placed;
};

inline constexpr int kWeirLayers = 6;

// weir_1_crop.jpg (640x480) as 3x2 layers of 260x280 (70-80 px overlaps), layer k seen as
// gain[k] (1 - v t) photo + offset[k], t = (r / half diagonal)^2 about the layer's centre, with
// offsets {0.12, -0.10, 0.05, -0.15, 0.08, 0}; no gains: 1. Float layers: nothing clips.
inline WeirLayers cut_weir(double v = 0.0, const double* gain = nullptr) {
  WeirLayers c;
  c.photo = read_image(GDP_TEST_DATA "/opencv/weir_1_crop.jpg").image;
  const double offset[kWeirLayers] = {0.12, -0.10, 0.05, -0.15, 0.08, 0.0};
  const int w = 260, h = 280;
  const double cx = (w - 1) / 2.0, cy = (h - 1) / 2.0, r2 = (w * w + h * h) / 4.0;
  for (int n = 0; n < kWeirLayers; ++n) {
    const int x0 = (n % 3) * 190, y0 = (n / 3) * 200;
    const double g = gain ? gain[n] : 1.0;
    Image l(w, h, 3);
    for (int ch = 0; ch < 3; ++ch)
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const double t = ((x - cx) * (x - cx) + (y - cy) * (y - cy)) / r2;
          l.at(ch, x, y) = static_cast<float>(g * (1.0 - v * t) * c.photo.at(ch, x0 + x, y0 + y) + offset[n]);
        }
    c.layers.push_back(std::move(l));
  }
  for (int n = 0; n < kWeirLayers; ++n) c.placed.push_back({&c.layers[n], nullptr, (n % 3) * 190, (n / 3) * 200});
  return c;
}

}  // namespace gdp::test
