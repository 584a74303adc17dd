// The HPX WCS of HiPS FITS tiles (HiPS 1.0's optional enabler): header cards placing each tile's pixels on the sky.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

namespace gdp::sky {

class Wcs;

// Cards for the tiles of order `order`, `width` pixels (HipsGeometry's convention), in the frame
// whose longitude axis is `longitude` ("RA", "GLON", "ELON"): the standard's form for tile 0/7
// for every tile, RA---HPX / DEC--HPX (GLON-HPX ...), CD = 45 / (2^order width) (-1, -1; 1, -1),
// PV2_1 = 4, PV2_2 = 3, CRVAL = 0, 0 (180, 0 for base pixel 6, which the HPX plane cuts at
// longitude 180 otherwise) and CRPIX where the tile lies in that plane. Not thread-safe.
class HipsTileWcs {
 public:
  HipsTileWcs(int order, int width, const std::string& longitude);
  ~HipsTileWcs();
  HipsTileWcs(const HipsTileWcs&) = delete;
  HipsTileWcs& operator=(const HipsTileWcs&) = delete;

  std::string cards(std::int64_t npix) const;

 private:
  std::string cards_for(double crval1, double crpix1, double crpix2) const;
  int order_, width_;
  std::string lon_axis_, lat_axis_;
  std::unique_ptr<Wcs> plane_[2];  // CRPIX 0, 0: CRVAL1 0 and 180
};

}  // namespace gdp::sky
