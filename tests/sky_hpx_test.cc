// The whole sky as an HPX FITS image (gdp sky --projection HPX): each pixel one HEALPix pixel, and output without -o.
#include <gtest/gtest.h>

#include <healpix_base.h>

#include <cmath>
#include <filesystem>
#include <set>

#include "cli_fixture.h"
#include "gdp/errors.h"
#include "gdp/image_io.h"
#include "io/fits_image.h"
#include "sky/header.h"
#include "sky/hips_files.h"
#include "sky/hips_geometry.h"
#include "sky/plate.h"
#include "sky/wcs.h"

namespace gdp {
namespace {

namespace fs = std::filesystem;

class SkyHpx : public test::CliFixture {
 protected:
  // A 24 x 24 TAN plate of 0.5 degree pixels at (120, -30), values 1 + x / 24.
  void plate(const std::string& name) {
    Image image(24, 24, 1);
    for (int y = 0; y < 24; ++y)
      for (int x = 0; x < 24; ++x) image.at(0, x, y) = 1.0f + x / 24.0f;
    WriteOptions options;
    options.fits_header = sky::target_header({{}, 120.0, -30.0, 24, 24, 0.5, "TAN"});
    write_image(path(name), image, options);
  }
};

// Every pixel wcslib places on the sky is the centre of a HEALPix pixel (healpix_cxx, 1e-10 rad), every
// HEALPix pixel is one image pixel, and pixel -> sky -> pixel comes back to 1e-6 pixel; the N
// pixels on the cut through base pixel 6 (longitude 180 in the HPX plane) appear at both ends.
TEST_F(SkyHpx, GridPixelsAreTheHealpixPixels) {
  for (const int order : {0, 2, 5}) {
    for (const char* frame : {"RA", "GLON"}) {
      const int n = 1 << order, size = 5 * n;
      const sky::Wcs wcs(sky::hpx_grid_header(order, frame), size, size, "hpx");
      const T_Healpix_Base<int64> healpix(order, NEST);
      std::set<std::int64_t> seen;
      long long placed = 0, back = 0;
      double worst_angle = 0.0, worst_back = 0.0;
      for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
          double lon = 0, lat = 0, u = 0, v = 0;
          if (!wcs.pixel_to_sky(x + 0.5, y + 0.5, lon, lat)) continue;
          ++placed;
          const sphere::Vec3 d = sky::direction(lon, lat);
          const std::int64_t p = healpix.vec2pix(vec3(d.x, d.y, d.z));
          const vec3 c = healpix.pix2vec(p);
          worst_angle = std::max(worst_angle, std::hypot(d.x - c.x, d.y - c.y, d.z - c.z));  // chord ~ angle
          seen.insert(p);
          ASSERT_TRUE(wcs.sky_to_pixel(lon, lat, u, v));
          const double e = std::max(std::abs(u - x - 0.5), std::abs(v - y - 0.5));
          if (e < 0.5) {
            ++back;
            worst_back = std::max(worst_back, e);
          }
        }
      SCOPED_TRACE(testing::Message() << "order " << order << ", " << frame);
      EXPECT_EQ(static_cast<long long>(seen.size()), 12LL * n * n) << "every HEALPix pixel once";
      EXPECT_EQ(placed, 12LL * n * n + n) << "and the cut's N pixels twice";
      EXPECT_EQ(back, 12LL * n * n);
      EXPECT_LT(worst_back, 1e-6);   // pixels
      EXPECT_LT(worst_angle, 1e-10);  // radians
    }
  }
}

TEST_F(SkyHpx, OrderForScaleAndRefusals) {
  EXPECT_EQ(sky::hpx_order_for_scale(60.0), 0);   // order 0 pixels are 58.6 degrees
  EXPECT_EQ(sky::hpx_order_for_scale(58.0), 1);
  EXPECT_EQ(sky::hpx_order_for_scale(0.11), 10);  // 0.057 degrees (0.115 at order 9)
  EXPECT_THROW(sky::hpx_grid_header(3, "XLON"), UsageError);
  EXPECT_THROW(sky::hpx_grid_header(14, "RA"), UsageError);
}

// One run writes the HPX image and a HiPS of the same HEALPix pixels (order 6 = tile order 2 +
// 16-pixel tiles): they sample the same PQ image at the same directions, so agree pixel by pixel.
// Without -o the HiPS alone comes out, tile for tile the same.
TEST_F(SkyHpx, AllSkyImageAgreesWithTheHipsTilesAndHipsNeedsNoImage) {
  plate("a.fits");
  const std::string plates = "sky " + path("a.fits") + " --pq-height 64 --hips-tile 16 --quiet";
  test::CliRun r = gdp(plates + " --projection HPX -o " + path("hpx.fits") + " --hips " + path("hips"));
  ASSERT_EQ(r.code, 0) << r.err;
  io::FitsImage file(path("hpx.fits"));
  ASSERT_EQ(file.width(), 320);  // 4 H^2 = 16384 PQ pixels -> order 6 (49152 pixels), N = 64
  const sky::Wcs wcs(file.header(), 320, 320, "hpx.fits");
  const Image hpx = read_image(path("hpx.fits")).image;
  const sky::HipsGeometry geometry(2, 16);
  std::vector<sphere::Vec3> dirs;
  long long compared = 0, finite_elsewhere = 0;
  double worst = 0.0;
  for (const auto& entry : fs::recursive_directory_iterator(path("hips/Norder2"))) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("Npix", 0) != 0 || entry.path().extension() != ".fits") continue;
    const std::int64_t npix = std::stoll(name.substr(4));
    const Image tile = read_image(entry.path()).image;
    geometry.tile_directions(npix, dirs);
    for (int k = 0; k < 256; ++k) {
      double lon = 0, lat = 0, x = 0, y = 0;
      sky::lon_lat(dirs[k], lon, lat);
      ASSERT_TRUE(wcs.sky_to_pixel(lon, lat, x, y));
      const float a = tile.data[k], b = hpx.at(0, static_cast<int>(x), static_cast<int>(y));
      ASSERT_EQ(std::isfinite(a), std::isfinite(b)) << "tile " << npix << " pixel " << k;
      if (std::isfinite(a)) worst = std::max(worst, double(std::abs(a - b))), ++compared;
    }
  }
  for (const float v : hpx.data) finite_elsewhere += std::isfinite(v);
  EXPECT_GT(compared, 30);
  EXPECT_EQ(finite_elsewhere, compared) << "the image has data only where the HiPS has";
  EXPECT_LT(worst, 1e-5);

  r = gdp(plates + " --hips " + path("alone"));
  ASSERT_EQ(r.code, 0) << r.err;
  const std::int64_t t = geometry.tile_of(sky::direction(120.0, -30.0));
  const fs::path stem = sky::hips_tile_stem(2, t).concat(".fits");
  const Image alone = read_image(path("alone") / stem).image, both = read_image(path("hips") / stem).image;
  int finite = 0;
  for (std::size_t k = 0; k < alone.data.size(); ++k) {
    ASSERT_EQ(std::isfinite(alone.data[k]), std::isfinite(both.data[k])) << k;
    if (!std::isfinite(alone.data[k])) continue;
    EXPECT_EQ(alone.data[k], both.data[k]) << k;
    ++finite;
  }
  EXPECT_GT(finite, 0);
  EXPECT_TRUE(fs::exists(path("alone/Moc.fits")));

  expect_failure("sky " + path("a.fits"), "needs an output: -o IMAGE, --hips DIR or --toast DIR");
  expect_failure(plates + " --center 120,-30 --size 20,20 --scale 0.5 --hips " + path("h3"), "give -o");
  expect_failure(plates + " --projection HPX --center 120,-30 -o " + path("x.fits"), "--projection HPX takes");
  EXPECT_FALSE(fs::exists(path("h3")));
}

}  // namespace
}  // namespace gdp
