// The files of a HiPS directory: tiles (FITS and PNG), properties, Moc.fits, the Allsky preview.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "gdp/image.h"

namespace gdp::sky {

// What every file needs to know about the HiPS.
struct HipsFormat {
  int order = 0, min_order = 0, width = 512;
  std::string frame = "equatorial";  // hips_frame: equatorial, galactic, ecliptic
  float lo = 0.0f, hi = 1.0f;        // PNG: grey = (value - lo) / (hi - lo), clamped; alpha = data
  float min = 0.0f, max = 1.0f;      // hips_data_range: the data's finite extremes
};

// "Norder{order}/Dir{D}/Npix{npix}" (D = npix / 10000 * 10000), without the extension.
std::filesystem::path hips_tile_stem(int order, std::int64_t npix);

// Writes the tile as Npix{npix}.fits (float, NaN where no data, `cards` in its header: the tile's
// WCS, hips_tile_wcs.h) and Npix{npix}.png (8-bit grey + alpha, transparent where no data) under
// `root`, creating directories.
void write_hips_tile(const std::filesystem::path& root, const HipsFormat& format, int order, std::int64_t npix,
                     const Image& tile, const std::string& cards);

// The `properties` file (HiPS 1.0, hips_version 1.4). `title`: obs_title; (ra, dec, fov): the ICRS
// initial view, degrees; `tiles`: hips_nb_tiles (per format); `sky_fraction`: moc_sky_fraction;
// `description`, `progenitor`: obs_description, prov_progenitor (left out when empty).
struct HipsProperties {
  std::string title;
  double ra = 0.0, dec = 0.0, fov = 180.0;
  long long tiles = 0;
  double sky_fraction = 0.0;
  std::string description, progenitor;
};
void write_hips_properties(const std::filesystem::path& file, const HipsFormat& format, const HipsProperties& p);

// The coverage `tiles` (indices of order `order`, ascending, in ICRS: hips_icrs.h) as an IVOA MOC
// in FITS (MOC 1.1 / 2.0: a binary table of NUNIQ = 4 * 4^k + npix cells, complete groups of four
// merged into their parent; COORDSYS 'C'). Returns the cells written.
std::vector<std::int64_t> write_moc(const std::filesystem::path& file, int order, const std::vector<std::int64_t>& tiles);

// Tiles of one order (0..3) packed into Norder{k}/Allsky.fits and .png: cols = floor(sqrt(12 *
// 4^k)) tiles a row, tile npix at column npix % cols, row npix / cols from the top, each tile
// reduced to min(64, width) pixels by finite means.
class HipsAllsky {
 public:
  HipsAllsky(int order, int width);
  int order() const { return order_; }
  void add(std::int64_t npix, const Image& tile);
  void write(const std::filesystem::path& root, const HipsFormat& format) const;

 private:
  int order_, width_, small_, cols_;
  Image image_;
};

}  // namespace gdp::sky
