// gdp sky --hips: the covered tiles found from the PQ image, the streamed pyramid, then properties, Moc.fits, Allsky.
#include "sky/hips_output.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "gdp/errors.h"
#include "io/staged_directory.h"
#include "sky/hips_files.h"
#include "sky/hips_geometry.h"
#include "sky/hips_icrs.h"
#include "sky/hips_pyramid.h"
#include "sky/hips_tile_wcs.h"
#include "sky/plate.h"
#include "sky/reproject.h"
#include "sphere/vec3.h"

namespace gdp::sky {

namespace fs = std::filesystem;

namespace {

// Tiles near covered PQ pixels (each one's tile and its neighbours: a tile is wider than a PQ
// pixel, so every tile pixel whose nearest PQ pixel is covered is in one of them), and the
// initial view: the covered pixels' mean direction and twice their largest distance from it.
struct Coverage {
  std::vector<std::int64_t> tiles;
  double ra = 0.0, dec = 0.0, fov = 180.0;
};

Coverage find_coverage(const PqStore& pq, const HipsGeometry& geometry) {
  const PqWindow& window = pq.window();
  std::vector<std::int64_t> tiles;
  std::vector<sphere::Vec3> dirs;
  std::vector<float> row(window.width);
  sphere::Vec3 sum;
  for (int j = 0; j < window.rows; ++j) {
    pq.read_row(j, row);
    for (int i = 0; i < window.width; ++i) {
      if (!std::isfinite(row[i])) continue;
      const sphere::Vec3 d = sphere::pq_pixel_direction(sphere::SquareMap::Toast, window.height, window.i0 + i, window.j0 + j);
      sum = sum + d;
      const std::int64_t t = geometry.tile_of(d);
      if (tiles.empty() || tiles.back() != t) tiles.push_back(t);
      if (i % 8 == 0 && j % 8 == 0) dirs.push_back(d);
    }
  }
  Coverage c;
  c.tiles = geometry.with_neighbours(std::move(tiles));
  if (sphere::norm(sum) > 1e-9) {
    const sphere::Vec3 centre = sphere::normalise(sum);
    lon_lat(centre, c.ra, c.dec);
    double widest = 0.0;
    for (const sphere::Vec3& d : dirs) widest = std::max(widest, sphere::angle(centre, d));
    c.fov = std::clamp(2.0 * widest * 180.0 / M_PI, 1e-3, 180.0);
  }
  return c;
}

std::string hips_frame(const std::string& longitude) {
  if (longitude == "RA") return "equatorial";
  if (longitude == "GLON") return "galactic";
  throw UsageError(fmt::format("gdp sky --hips: plates in RA/Dec or galactic coordinates, not {}", longitude));
}

HipsSummary write_tree(const PqStore& pq, const HipsGeometry& geometry, HipsFormat& format, const HipsOptions& options,
                       const std::string& longitude, const fs::path& root) {
  Coverage coverage = find_coverage(pq, geometry);
  if (format.frame == "galactic") galactic_to_icrs(coverage.ra, coverage.dec);  // hips_initial_ra/dec are ICRS
  PqSampler sampler(pq);  // holds the PQ rows of one tile at a time
  std::vector<sphere::Vec3> dirs;
  const int threads = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  const HipsSample sample = [&](std::int64_t npix, Image& tile) {
    geometry.tile_directions(npix, dirs);
    sampler.sample(dirs, tile.data, threads);
    return std::any_of(tile.data.begin(), tile.data.end(), [](float v) { return std::isfinite(v); });
  };
  HipsAllsky allsky(std::min(3, format.order), format.width);
  MocCells moc(geometry, format.frame == "galactic");
  HipsSummary s;
  s.order = format.order;
  std::vector<std::unique_ptr<HipsTileWcs>> wcs;  // per order
  for (int k = 0; k <= format.order; ++k) wcs.push_back(std::make_unique<HipsTileWcs>(k, format.width, longitude));
  const HipsEmit emit = [&](int order, std::int64_t npix, const Image& tile) {
    write_hips_tile(root, format, order, npix, tile, wcs[order]->cards(npix));
    ++s.tiles;
    if (order == format.order) {
      moc.add(npix, tile);
      ++s.deepest_tiles;
    }
    if (order == allsky.order()) allsky.add(npix, tile);
  };
  build_hips_pyramid(format.order, format.min_order, format.width, coverage.tiles, sample, emit);
  allsky.write(root, format);
  const std::vector<std::int64_t> cells = write_moc(root / "Moc.fits", format.order, moc.cells());
  HipsProperties p{options.title, coverage.ra, coverage.dec, coverage.fov, 2 * s.tiles, 0.0, options.description,
                   options.progenitor};
  for (const std::int64_t uniq : cells) {
    int k = 0;
    while ((std::int64_t{4} << (2 * (k + 1))) <= uniq) ++k;
    p.sky_fraction += std::ldexp(1.0, -2 * k) / 12.0;
  }
  write_hips_properties(root / "properties", format, p);
  return s;
}

}  // namespace

void check_hips_output(const fs::path& dir, const HipsOptions& options, const std::string& longitude) {
  hips_frame(longitude);
  const int w = options.tile_width;
  if (w < 8 || w > 4096 || (w & (w - 1)) != 0)
    throw UsageError(fmt::format("--hips-tile {}: a power of 2 from 8 to 4096 (HiPS tiles are 512 by default)", w));
  std::error_code ec;
  if (fs::exists(dir, ec) && !(fs::is_directory(dir, ec) && fs::is_empty(dir, ec)))
    throw UsageError(dir.string() + ": exists and is not an empty directory");
}

HipsSummary write_sky_hips(const PqStore& pq, const std::string& longitude, const fs::path& out,
                           const HipsOptions& options) {
  const PqWindow& window = pq.window();
  check_hips_output(out, options, longitude);
  HipsFormat format;
  format.frame = hips_frame(longitude);
  format.width = options.tile_width;
  const int shift = static_cast<int>(std::lround(std::log2(format.width)));
  format.order = std::max(0, hips_pixel_order(window.height) - shift);
  std::tie(format.lo, format.hi) = display_range(pq);
  format.min = format.lo;
  format.max = format.hi;
  std::vector<float> row(static_cast<std::size_t>(window.width));
  for (int j = 0; j < window.rows; ++j) {  // hips_data_range: every covered pixel, row by row
    pq.read_row(j, row);
    for (const float v : row)
      if (std::isfinite(v)) format.min = std::min(format.min, v), format.max = std::max(format.max, v);
  }
  const HipsGeometry geometry(format.order, format.width);
  HipsSummary s;
  io::write_staged_directory(out, [&](const fs::path& temp) { s = write_tree(pq, geometry, format, options, longitude, temp); });
  return s;
}

HipsSummary write_sky_hips(const Image& pq, const PqWindow& window, const std::string& longitude, const fs::path& out,
                           const HipsOptions& options) {
  return write_sky_hips(PqStore(pq, window), longitude, out, options);
}

}  // namespace gdp::sky
