// What HiPS 1.0 wants in ICRS whatever the HiPS's frame: the initial view and the Moc.fits cells of a galactic HiPS.
#pragma once

#include <cstdint>
#include <vector>

#include "gdp/image.h"
#include "sky/hips_geometry.h"

namespace gdp::sky {

// Galactic (l, b) -> ICRS (RA, Dec), degrees in place: wcslib's sphx2s with the galactic pole at
// RA 192.85948, Dec 27.12825 and the celestial pole at l 122.93192 (the Hipparcos/FK5 J2000
// definition; astropy's ICRS differs by the FK5 frame bias, tens of milliarcseconds).
void galactic_to_icrs(double& lon, double& lat);

// The cells of order geometry.order() that Moc.fits lists. MOC 1.1, which HiPS 1.0's Moc.fits
// follows, is ICRS only (Aladin's LINT checks COORDSYS = 'C'): for an equatorial HiPS the deepest
// tiles written; for a galactic one the ICRS cells holding the centre of a finite pixel of them
// (a cell that data enters by less than a pixel's width can be missed).
class MocCells {
 public:
  MocCells(const HipsGeometry& geometry, bool galactic) : geometry_(geometry), galactic_(galactic) {}
  void add(std::int64_t npix, const Image& tile);  // a deepest tile as written
  std::vector<std::int64_t> cells() const;          // ascending, unique

 private:
  const HipsGeometry& geometry_;
  bool galactic_;
  std::vector<std::int64_t> cells_;
  std::vector<sphere::Vec3> dirs_;
};

}  // namespace gdp::sky
