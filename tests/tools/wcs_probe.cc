// Test tool: prints gdp's pixel -> sky positions (and pixel values) of a FITS image or header template for tests/sky_astropy_test.py.
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "gdp/errors.h"
#include "io/fits_image.h"
#include "sky/header.h"
#include "sky/wcs.h"

// Usage: gdp_wcs_probe FILE.fits | TEMPLATE.hdr
// Prints "size W H" then, on a grid of 9 x 9 points over the image (edges, centres and
// fractions), "pix X Y LON LAT" in gdp's pixel coordinates (rows top down); for FITS images
// also "val X Y V" for the pixel (X, Y) of integer coordinates.
int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: gdp_wcs_probe FILE.fits|TEMPLATE.hdr\n");
    return 2;
  }
  try {
    const std::string path = argv[1];
    const bool fits = path.size() < 4 || path.substr(path.size() - 4) != ".hdr";
    std::string header;
    int w = 0, h = 0;
    std::vector<float> pixels;
    if (fits) {
      gdp::io::FitsImage image(path);
      header = image.header();
      w = image.width();
      h = image.height();
      pixels.resize(static_cast<std::size_t>(w) * h);
      image.read(0, 0, h, 0, w, pixels.data());
    } else {
      header = gdp::sky::read_header_template(path);
      w = static_cast<int>(gdp::sky::header_number(header, "NAXIS1").value_or(0));
      h = static_cast<int>(gdp::sky::header_number(header, "NAXIS2").value_or(0));
    }
    gdp::sky::Wcs wcs(header, w, h, path);
    std::printf("size %d %d\n", w, h);
    for (int a = 0; a <= 8; ++a)
      for (int b = 0; b <= 8; ++b) {
        const double x = w * a / 8.0 + 0.13 * (a % 3), y = h * b / 8.0 + 0.29 * (b % 2);
        double lon = 0, lat = 0;
        if (wcs.pixel_to_sky(x, y, lon, lat)) std::printf("pix %.6f %.6f %.12f %.12f\n", x, y, lon, lat);
        if (fits && a < 8 && b < 8) {
          const int i = w * a / 8, j = h * b / 8;
          std::printf("val %d %d %.9g\n", i, j, pixels[static_cast<std::size_t>(j) * w + i]);
        }
      }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
  return 0;
}
