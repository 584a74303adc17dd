// Shared by the sky tests: plates written from a sky function, and a written FITS file carrying a template's WCS.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <string>

#include "gdp/image.h"
#include "gdp/image_io.h"
#include "gdp/sky.h"
#include "io/fits_image.h"
#include "sky/header.h"
#include "sky/plate.h"
#include "sky/wcs.h"
#include "sphere/vec3.h"

namespace gdp::test {

using SkyFunction = std::function<double(const sphere::Vec3&)>;

// Writes a TAN plate of `size` x `size` pixels of `scale` degrees centred at (lon, lat): the
// sky function at each pixel centre plus `offset` (plus `background` of the pixel coordinates);
// returns its path.
inline std::string write_plate(const std::filesystem::path& dir, const std::string& name, double lon, double lat,
                               int size, double scale, const SkyFunction& sky, double offset,
                               const std::function<double(double, double)>& background = {}) {
  SkyTarget grid{{}, lon, lat, size, size, scale, "TAN"};
  const std::string cards = sky::target_header(grid);
  const sky::Wcs wcs(cards, size, size, name);
  Image image(size, size, 1);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      double a = 0, b = 0;
      EXPECT_TRUE(wcs.pixel_to_sky(x + 0.5, y + 0.5, a, b));
      image.at(0, x, y) = static_cast<float>(sky(sky::direction(a, b)) + offset +
                                             (background ? background(x + 0.5, y + 0.5) : 0.0));
    }
  WriteOptions options;
  options.fits_header = cards;
  const std::filesystem::path path = dir / name;
  write_image(path, image, options);
  return path.string();
}

// The FITS file's header maps a pixel to the sky as the template (Montage's form) does.
inline void expect_template_wcs(const std::string& fits, const std::string& hdr) {
  io::FitsImage out(fits);
  const int w = out.width(), h = out.height();
  const sky::Wcs written(out.header(), w, h, fits), asked(sky::read_header_template(hdr), w, h, hdr);
  double a = 0, b = 0, c = 0, d = 0;
  ASSERT_TRUE(written.pixel_to_sky(w * 0.3 + 0.5, h * 0.6 + 0.25, a, b));
  ASSERT_TRUE(asked.pixel_to_sky(w * 0.3 + 0.5, h * 0.6 + 0.25, c, d));
  EXPECT_DOUBLE_EQ(a, c);
  EXPECT_DOUBLE_EQ(b, d);
}

}  // namespace gdp::test
