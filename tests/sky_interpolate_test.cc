// sky/interpolate.h against mathematics: Catmull-Rom is exact on quadratics and at pixel centres, bilinear next to blanks.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "sky/interpolate.h"

namespace gdp::sky {
namespace {

constexpr int kW = 12, kH = 9;

// Pixel (i, j) holds f at its centre (i + 0.5, j + 0.5).
template <class F>
std::vector<float> grid(F&& f) {
  std::vector<float> v(kW * kH);
  for (int j = 0; j < kH; ++j)
    for (int i = 0; i < kW; ++i) v[j * kW + i] = static_cast<float>(f(i + 0.5, j + 0.5));
  return v;
}

double quadratic(double x, double y) { return 0.3 + 0.05 * x - 0.02 * y + 0.004 * x * x - 0.003 * x * y + 0.006 * y * y; }

TEST(SkyInterpolate, CatmullRomIsExactOnQuadratics) {
  const std::vector<float> v = grid(quadratic);
  double worst = 0.0, bilinear_worst = 0.0;
  for (double y = 2.0; y <= kH - 2.0; y += 0.173)
    for (double x = 2.0; x <= kW - 2.0; x += 0.191) {
      worst = std::max(worst, std::abs(interpolate_clamped(v.data(), kW, kH, x, y) - quadratic(x, y)));
      bilinear_worst = std::max(bilinear_worst, std::abs(bilinear_clamped(v.data(), kW, kH, x, y) - quadratic(x, y)));
    }
  EXPECT_LE(worst, 1e-6) << "the cubic reproduces quadratics";
  EXPECT_GE(bilinear_worst, 5e-4) << "bilinear does not (the test can fail)";
}

TEST(SkyInterpolate, PixelCentresAreTheirValues) {
  const std::vector<float> v = grid([](double x, double y) { return std::sin(x) * std::cos(1.7 * y); });
  for (int j = 0; j < kH; ++j)
    for (int i = 0; i < kW; ++i)
      EXPECT_NEAR(interpolate_clamped(v.data(), kW, kH, i + 0.5, j + 0.5), v[j * kW + i], 1e-6) << i << " " << j;
}

TEST(SkyInterpolate, NextToABlankItIsBilinearAmongTheFinite) {
  std::vector<float> v = grid(quadratic);
  v[4 * kW + 5] = std::numeric_limits<float>::quiet_NaN();
  // Within two pixels of the blank the cubic's 4 x 4 meets it: bilinear among the finite ones.
  for (double y = 3.0; y <= 6.0; y += 0.25)
    for (double x = 4.0; x <= 7.0; x += 0.25) {
      const float got = interpolate_clamped(v.data(), kW, kH, x, y), bilinear = bilinear_clamped(v.data(), kW, kH, x, y);
      EXPECT_TRUE(got == bilinear || (std::isnan(got) && std::isnan(bilinear))) << x << " " << y;
      // Finite except at the blank's own centre (bilinear's only weight there is the blank's).
      EXPECT_EQ(std::isnan(got), x == 5.5 && y == 4.5) << x << " " << y;
    }
  // Far from it, the cubic.
  EXPECT_NEAR(interpolate_clamped(v.data(), kW, kH, 9.3, 2.2), quadratic(9.3, 2.2), 1e-6);
}

TEST(SkyInterpolate, NaNWhereTheFourNearestAreBlank) {
  std::vector<float> v = grid(quadratic);
  for (int j = 3; j < 5; ++j)
    for (int i = 3; i < 5; ++i) v[j * kW + i] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_TRUE(std::isnan(interpolate_clamped(v.data(), kW, kH, 4.0, 4.0)));
  EXPECT_TRUE(std::isfinite(interpolate_clamped(v.data(), kW, kH, 5.2, 4.0)));
}

}  // namespace
}  // namespace gdp::sky
