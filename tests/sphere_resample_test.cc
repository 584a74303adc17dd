// Resampling between equirectangular, PQ and cube maps: real-image round trip, smooth functions,
// continuity at the meridian and the poles, nearest neighbour for labels, conventions.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "gdp/errors.h"
#include "gdp/image_io.h"
#include "gdp/sphere.h"

namespace gdp::sphere {
namespace {

constexpr double kPi = std::numbers::pi;

// PSNR (peak 1) over the rows whose latitude is within +-max_lat degrees.
double psnr_equirect(const Image& a, const Image& b, double max_lat) {
  double se = 0.0;
  long long n = 0;
  for (int c = 0; c < a.channels; ++c)
    for (int y = 0; y < a.height; ++y) {
      const double lat = 90.0 - 180.0 * (y + 0.5) / a.height;
      if (std::abs(lat) >= max_lat) continue;
      for (int x = 0; x < a.width; ++x) {
        const double d = double(a.at(c, x, y)) - b.at(c, x, y);
        se += d * d;
        ++n;
      }
    }
  return 10.0 * std::log10(1.0 / (se / n));
}

TEST(SphereResample, RealMapRoundTripThroughPq) {
  const auto t0 = std::chrono::steady_clock::now();
  const Image src = read_image(GDP_SHARED_DATA "/equirect/three-globe-npm/earth-blue-marble.jpg").image;
  ASSERT_EQ(src.width, 4096);
  const int h = default_pq_height(static_cast<long long>(src.width) * src.height);
  const auto t1 = std::chrono::steady_clock::now();
  const Image pq = resample(src, {Layout::Equirect}, {Layout::Pq}, 4 * h, h);
  const auto t2 = std::chrono::steady_clock::now();
  const Image back = resample(pq, {Layout::Pq}, {Layout::Equirect}, src.width, src.height);
  const auto t3 = std::chrono::steady_clock::now();
  const double psnr = psnr_equirect(src, back, 80.0);
  auto secs = [](auto a, auto b) { return std::chrono::duration<double>(b - a).count(); };
  std::printf("equirect 4096x2048 -> PQ %dx%d -> equirect: PSNR %.2f dB (|lat| < 80), all rows %.2f dB; "
              "read %.2fs, to-pq %.2fs, from-pq %.2fs\n",
              4 * h, h, psnr, psnr_equirect(src, back, 90.0), secs(t0, t1), secs(t1, t2), secs(t2, t3));
  EXPECT_GE(psnr, 40.0);
}

}  // namespace
}  // namespace gdp::sphere
