// HiPS tile geometry on HEALPix (nested): the order a PQ sphere supports, tile pixel directions, tiles near data.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "gdp/sphere.h"

namespace gdp::sky {

// The HEALPix order of the HiPS pixels for a PQ sphere of height `pq_height`: the coarsest whose
// pixels are not larger than the PQ image's mean pixel (12 * 4^n >= 4 H^2).
int hips_pixel_order(int pq_height);

// Tiles of order `order`, `width` x `width` pixels (width = 2^shift), in the HiPS convention
// (docs/sky.md): pixel (column c, row r) of a tile, rows top down as gdp stores images (the
// way PNG tiles store them; FITS tiles store the same rows bottom up), is the HEALPix pixel of
// order `order + shift` with nested index npix * width^2 + interleave(r, c), r in the even bits
// (HEALPix's x: north-east from the south corner of the tile) and c in the odd bits (y:
// north-west). The standard's example WCS of tile 0/7 (RA---HPX) describes the same pixels
// (tests/sky_hips_test.cc).
class HipsGeometry {
 public:
  HipsGeometry(int order, int width);
  ~HipsGeometry();
  HipsGeometry(const HipsGeometry&) = delete;
  HipsGeometry& operator=(const HipsGeometry&) = delete;

  int order() const { return order_; }
  int width() const { return width_; }
  // Directions (x: RA 0, z: the pole, as sky::direction) of tile `npix`'s pixel centres, row-major.
  void tile_directions(std::int64_t npix, std::vector<sphere::Vec3>& out) const;
  // The tile holding direction `d`.
  std::int64_t tile_of(const sphere::Vec3& d) const;
  // `tiles` (any order, repeats allowed) with every tile touching one of them, sorted, unique.
  std::vector<std::int64_t> with_neighbours(std::vector<std::int64_t> tiles) const;

 private:
  struct Bases;
  int order_, width_;
  std::unique_ptr<Bases> bases_;
};

}  // namespace gdp::sky
