// HiPS tile geometry with HEALPix C++ (Debian libhealpix-cxx-dev): nested indices <-> directions, neighbours.
#include "sky/hips_geometry.h"

#include <algorithm>
#include <cmath>

#include <healpix_base.h>

#include "gdp/errors.h"

namespace gdp::sky {

struct HipsGeometry::Bases {
  T_Healpix_Base<int64> tiles, pixels;
};

int hips_pixel_order(int pq_height) {
  const double pq_pixels = 4.0 * double(pq_height) * pq_height;
  int n = 0;
  while (12.0 * std::pow(4.0, n) < pq_pixels) ++n;
  return n;
}

HipsGeometry::HipsGeometry(int order, int width) : order_(order), width_(width) {
  int shift = 0;
  while ((1 << shift) < width) ++shift;
  if (width < 1 || (1 << shift) != width) throw UsageError("HiPS tile width must be a power of 2");
  if (order < 0 || order + shift > 29) throw UsageError("HiPS order + log2(tile width) must be at most 29");
  bases_ = std::make_unique<Bases>(Bases{T_Healpix_Base<int64>(order, NEST), T_Healpix_Base<int64>(order + shift, NEST)});
}

HipsGeometry::~HipsGeometry() = default;

void HipsGeometry::tile_directions(std::int64_t npix, std::vector<sphere::Vec3>& out) const {
  int tx = 0, ty = 0, face = 0;
  bases_->tiles.pix2xyf(npix, tx, ty, face);
  out.resize(static_cast<std::size_t>(width_) * width_);
  for (int r = 0; r < width_; ++r)
    for (int c = 0; c < width_; ++c) {
      // Row r is HEALPix x (the even bits of the nested index), column c is y.
      const vec3 v = bases_->pixels.pix2vec(bases_->pixels.xyf2pix(tx * width_ + r, ty * width_ + c, face));
      out[static_cast<std::size_t>(r) * width_ + c] = {v.x, v.y, v.z};
    }
}

std::int64_t HipsGeometry::tile_of(const sphere::Vec3& d) const { return bases_->tiles.vec2pix(vec3(d.x, d.y, d.z)); }

std::vector<std::int64_t> HipsGeometry::with_neighbours(std::vector<std::int64_t> tiles) const {
  std::sort(tiles.begin(), tiles.end());
  tiles.erase(std::unique(tiles.begin(), tiles.end()), tiles.end());
  const std::size_t n = tiles.size();
  fix_arr<int64, 8> around;
  for (std::size_t k = 0; k < n; ++k) {
    bases_->tiles.neighbors(tiles[k], around);
    for (int m = 0; m < 8; ++m)
      if (around[m] >= 0) tiles.push_back(around[m]);
  }
  std::sort(tiles.begin(), tiles.end());
  tiles.erase(std::unique(tiles.begin(), tiles.end()), tiles.end());
  return tiles;
}

}  // namespace gdp::sky
