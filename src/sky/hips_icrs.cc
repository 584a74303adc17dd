// Galactic -> ICRS for HiPS metadata (wcslib sph.h), and the ICRS cells of a galactic HiPS's coverage.
#include "sky/hips_icrs.h"

#include <algorithm>
#include <cmath>

#include <wcslib/sph.h>

#include "sky/plate.h"

namespace gdp::sky {

void galactic_to_icrs(double& lon, double& lat) {
  const double colat = 90.0 - 27.12825;
  const double eul[5] = {192.85948, colat, 122.93192, std::cos(colat * M_PI / 180.0), std::sin(colat * M_PI / 180.0)};
  double ra = 0.0, dec = 0.0;
  sphx2s(eul, 1, 1, 1, 1, &lon, &lat, &ra, &dec);
  lon = ra < 0.0 ? ra + 360.0 : ra;
  lat = dec;
}

void MocCells::add(std::int64_t npix, const Image& tile) {
  if (!galactic_) {
    cells_.push_back(npix);
    return;
  }
  geometry_.tile_directions(npix, dirs_);
  for (std::size_t k = 0; k < dirs_.size(); ++k) {
    if (!std::isfinite(tile.data[k])) continue;
    double lon = 0, lat = 0;
    lon_lat(dirs_[k], lon, lat);
    galactic_to_icrs(lon, lat);
    const std::int64_t cell = geometry_.tile_of(direction(lon, lat));
    if (cells_.empty() || cells_.back() != cell) cells_.push_back(cell);
  }
}

std::vector<std::int64_t> MocCells::cells() const {
  std::vector<std::int64_t> c = cells_;
  std::sort(c.begin(), c.end());
  c.erase(std::unique(c.begin(), c.end()), c.end());
  return c;
}

}  // namespace gdp::sky
