// Sky mosaics (gdp sky): FITS plates with WCS reprojected onto the PQ sphere, blended there, written for a target WCS.
#pragma once

#include <array>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "gdp/image_io.h"
#include "gdp/solver.h"

namespace gdp {

// The output image's grid: a header template (Montage's form, `header`), or a centre, size,
// pixel scale and projection (equatorial, RA increasing to the left), or projection "HPX" with no
// size: the whole sky on HEALPix pixels (5N x 5N, sky/header.h hpx_grid_header) of the order
// whose pixels are at most `scale` degrees, or (scale 0) of the HiPS's deepest pixels, in the
// plates' frame.
struct SkyTarget {
  std::filesystem::path header;  // non-empty: the template (NAXIS1/2 and the WCS keywords)
  double lon = 0.0, lat = 0.0;   // centre, degrees
  int width = 0, height = 0;     // pixels
  double scale = 0.0;            // degrees per pixel
  std::string projection = "TAN";  // any wcslib projection code: TAN, CAR, SIN, ZEA, ...
};

struct SkyOptions {
  SkyTarget target;
  long plane = 0;      // 0-based plane of cube plates
  int pq_height = 0;   // 0: from the finest plate scale
  bool blend = true;   // false: the seamed mosaic only (each point from the plate it lies deepest inside)
  // Before the solve, fit each plate's smooth background (plane + radial term in its own pixel
  // coordinates) to the overlaps and subtract it (docs/sky.md); the damping picks the smallest
  // fit where the overlaps cannot tell (relative to the data's mean diagonal).
  bool fit_backgrounds = true;
  double background_damping = 1e-3;
  // Seams go around the stars in the overlaps (each star from one plate: docs/sky.md, "Seams
  // around stars"); false: the plain rule, each point from the plate it lies deepest inside.
  bool star_seams = true;
  // Graph-cut seams (docs/sky.md, "Graph-cut seams"): the seams above moved through the overlaps
  // to where the plates (levelled, backgrounds off) agree best; stars still kept whole.
  bool graphcut_seams = false;
  // Non-empty: the stars that place the seams are found in these plates (one per plate, in the
  // same order, on the same grids: e.g. another band of the same plates), not in the plates.
  std::vector<std::string> seam_plates;
  // Non-empty: also a WorldWideTelescope TOAST pyramid there (new or empty directory; PNG grey +
  // alpha, 0.5-99.5 percentile stretch); the PQ height is then rounded up to 128 * 2^n.
  std::filesystem::path toast;
  // Non-empty: also a HiPS directory there (new or empty; IVOA HiPS 1.0, docs/sky.md): HEALPix
  // tiles hips_tile pixels wide (a power of 2) as FITS and PNG, properties, Moc.fits, Allsky.
  std::filesystem::path hips;
  int hips_tile = 512;
  std::function<void(const std::string&)> note;  // notes for the user (cubes, plates not used)
};

struct SkySummary {
  int pq_height = 0;
  std::array<int, 4> pq_window{};       // the PQ columns and rows solved: i0, j0, width, rows
  std::vector<long long> plate_pixels;  // PQ pixels taken from each plate
  long long covered = 0, target_pixels = 0;  // target pixels with a value, of all
  int hips_order = -1;                       // with `hips`: the deepest tile order and the tiles written
  long long hips_tiles = 0;
  // Per plate, the fitted background taken off (fit_backgrounds): offset, slope u, slope v, radial
  // (sky/plate_backgrounds.h), and its smooth terms' rms over the plate; empty when not fitted.
  std::vector<std::array<double, 4>> backgrounds;
  std::vector<double> background_rms;
  // The most plates whose pixels were in memory at once (every pass), and the most whose PQ rows
  // (and the solve's few cached rows after) meet one PQ row: plates_held <= plates_crossing.
  std::size_t plates_held = 0, plates_crossing = 0;
  // PQ pixels of the seamed mosaic this process computed: under mpirun on a PQ window, each rank
  // its columns and their halo only.
  long long mosaic_pixels = 0;
  // graphcut_seams: the seam cost of the distance seams and of the seams taken (rank 0's).
  double seam_cost_depth = 0, seam_cost = 0;
  // Plate pixels each rank read from the files over every pass and the solve (a plate read again
  // counted again; one entry without mpirun), and the pixels of all plates (--seams-from's too).
  std::vector<long long> plate_pixels_read;
  long long plate_pixels_in_files = 0;
  SolveSummary solve;
};

// Reads the plates (FITS with a celestial WCS, all in the target's frame), builds the seamed
// mosaic on a PQ sphere, solves the gradient-domain stitch there (solver.domain is set to
// spherical; the mean over the covered PQ pixels is the seamed mosaic's: docs/sky.md) and
// writes `out` on the target's grid, the WCS written into FITS headers. Pixels no plate covers
// are NaN. `out` empty: no image and no target (then options.hips or options.toast; the frame
// is the plates'). Under mpirun every rank solves its columns and rank 0 alone writes the
// outputs (the other ranks' summaries stop before them). Throws InputError naming the file (no WCS, a WCS wcslib rejects, a plane out of
// range, a target no plate reaches), UsageError for inconsistent options, OutputError.
void sky_mosaic(const std::vector<std::string>& plates, const SkyOptions& options, SolverOptions solver,
                const std::filesystem::path& out, WriteOptions write, SkySummary* summary = nullptr);

}  // namespace gdp
