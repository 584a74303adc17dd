// A sky mosaic's PQ image as a HiPS directory (IVOA HiPS 1.0): HEALPix tiles, properties, Moc.fits, Allsky.
#pragma once

#include <filesystem>
#include <string>

#include "gdp/image.h"
#include "sky/pq_store.h"
#include "sky/pq_window.h"

namespace gdp::sky {

struct HipsOptions {
  int tile_width = 512;  // hips_tile_width: a power of 2, 8 .. 4096
  std::string title = "gdp sky mosaic";
  std::string description = {}, progenitor = {};  // obs_description, prov_progenitor (none when empty)
};

struct HipsSummary {
  int order = 0;               // hips_order (deepest tile order)
  long long deepest_tiles = 0;  // tiles of that order (each as .fits and .png)
  long long tiles = 0;          // of every order
};

// UsageError when `dir` exists and is not an empty directory, the tile width is not allowed, or
// the plates' longitude axis (`longitude`, "RA" or "GLON") has no HiPS frame.
void check_hips_output(const std::filesystem::path& dir, const HipsOptions& options, const std::string& longitude);

// Writes `dir` from `pq` (a window of a TOAST PQ image of the sky, one channel, NaN where no plate
// is; read row by row, a tile's rows held at a time), in the plates' frame (`longitude`: the WCS longitude type, "RA" or "GLON"). The deepest
// order is the coarsest whose pixels are as fine as the PQ image's (hips_geometry.h); each tile
// pixel is the PQ image's bilinear value at its centre's direction (as gdp sky's FITS output),
// lower orders are 2x2 means down to order 0. Only tiles with data are written. Built in a hidden
// directory beside `dir` and renamed into place (removed on errors). Throws UsageError (frame,
// options), OutputError.
HipsSummary write_sky_hips(const PqStore& pq, const std::string& longitude, const std::filesystem::path& dir,
                           const HipsOptions& options);
// The same from an image in memory (`window.width` x `window.rows`).
HipsSummary write_sky_hips(const Image& pq, const PqWindow& window, const std::string& longitude,
                           const std::filesystem::path& dir, const HipsOptions& options);

}  // namespace gdp::sky
