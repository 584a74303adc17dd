// HPX header cards for HiPS tiles: the tile's first pixel placed in the HPX plane by wcslib, CRPIX from it.
#include "sky/hips_tile_wcs.h"

#include <cmath>
#include <tuple>
#include <vector>

#include <fmt/format.h>

#include "gdp/errors.h"
#include "sky/header.h"
#include "sky/hips_geometry.h"
#include "sky/plate.h"
#include "sky/wcs.h"

namespace gdp::sky {

HipsTileWcs::HipsTileWcs(int order, int width, const std::string& longitude) : order_(order), width_(width) {
  std::tie(lon_axis_, lat_axis_) = hpx_ctypes(longitude);
  for (int k = 0; k < 2; ++k)
    plane_[k] = std::make_unique<Wcs>(cards_for(180.0 * k, 0.0, 0.0), width, width, "the HiPS tiles' HPX plane");
}

HipsTileWcs::~HipsTileWcs() = default;

std::string HipsTileWcs::cards_for(double crval1, double crpix1, double crpix2) const {
  const double cd = 45.0 / (std::ldexp(1.0, order_) * width_);
  const auto number = [](double v) { return fmt::format("{:.17g}", v); };
  return card("CTYPE1", "'" + lon_axis_ + "'") + card("CTYPE2", "'" + lat_axis_ + "'") + card("CRPIX1", number(crpix1)) +
         card("CRPIX2", number(crpix2)) + card("CRVAL1", number(crval1)) + card("CRVAL2", "0.0") +
         card("CD1_1", number(-cd)) + card("CD1_2", number(-cd)) + card("CD2_1", number(cd)) + card("CD2_2", number(-cd)) +
         card("PV2_1", "4") + card("PV2_2", "3");
}

std::string HipsTileWcs::cards(std::int64_t npix) const {
  // The tile's top-left pixel (column 0, row 0: FITS pixel (1, width)) where the plane with
  // CRPIX (0, 0) puts it; pixels are half-integers there, so rounding to 1/2 makes CRPIX exact.
  const HipsGeometry geometry(order_, width_);
  std::vector<sphere::Vec3> dirs;
  geometry.tile_directions(npix, dirs);
  const bool six = (npix >> (2 * order_)) == 6;
  double lon = 0, lat = 0, x = 0, y = 0;
  lon_lat(dirs.front(), lon, lat);
  if (!plane_[six]->sky_to_pixel(lon, lat, x, y))
    throw OutputError(fmt::format("HiPS tile {}/{}: no place in the HPX plane", order_, npix));
  const double p1 = x + 0.5, p2 = width_ + 0.5 - y;  // FITS pixel coordinates
  const auto half = [](double v) { return std::round(2.0 * v) / 2.0; };
  return cards_for(six ? 180.0 : 0.0, half(1.0 - p1), half(width_ - p2));
}

}  // namespace gdp::sky
