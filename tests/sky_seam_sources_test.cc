// The stars the sky seams go around: found once each, at their peaks, with radii that grow with their size.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "sky/seam_sources.h"

namespace gdp::sky {
namespace {

struct Star {
  double x, y, sigma, peak;
};

// A 128 x 128 plate (pixels only): a sloped, gently curved sky plus Gaussian stars.
Plate plate_with(const std::vector<Star>& stars) {
  Plate p;
  p.width = p.height = 128;
  p.pixels.resize(128 * 128);
  for (int y = 0; y < 128; ++y)
    for (int x = 0; x < 128; ++x) {
      double v = 0.3 + 0.002 * x + 0.05 * std::sin(x / 17.0) * std::cos(y / 23.0);
      for (const Star& s : stars) {
        const double r2 = (x + 0.5 - s.x) * (x + 0.5 - s.x) + (y + 0.5 - s.y) * (y + 0.5 - s.y);
        v += s.peak * std::exp(-r2 / (2.0 * s.sigma * s.sigma));
      }
      p.pixels[y * 128 + x] = static_cast<float>(v);
    }
  return p;
}

TEST(SkySeamSources, EachStarOnceAtItsPeakWithItsExtent) {
  const std::vector<Star> stars = {{40.3, 60.6, 1.5, 1.0}, {90.0, 30.0, 3.0, 0.5}, {70.5, 100.5, 1.0, 0.2}};
  const std::vector<PlateSource> found = plate_sources(plate_with(stars));
  ASSERT_EQ(found.size(), stars.size());
  for (std::size_t k = 0; k < stars.size(); ++k) {
    const Star& s = stars[k];
    const PlateSource* match = nullptr;
    for (const PlateSource& f : found)
      if (std::abs(f.x + 0.5 - s.x) <= 1.0 && std::abs(f.y + 0.5 - s.y) <= 1.0) match = &f;
    ASSERT_NE(match, nullptr) << "star " << k;
    // Where a Gaussian's fall per pixel is under 1e-3 of its drop: about 3.7 sigma (whole pixels), plus one.
    EXPECT_GT(match->radius, 2.5 * s.sigma) << "star " << k;
    EXPECT_LT(match->radius, 5.0 * s.sigma + 2.5) << "star " << k;
  }
}

TEST(SkySeamSources, ASkyWithoutStarsHasNone) { EXPECT_TRUE(plate_sources(plate_with({})).empty()); }

}  // namespace
}  // namespace gdp::sky
