// Montage-compatible planar sky mosaics (gdp sky --projected): images already on one template, placed by their WCS and blended.
#pragma once

#include <array>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "gdp/blend.h"
#include "gdp/image_io.h"
#include "gdp/solver.h"

namespace gdp {

// One image reprojected onto the template (Montage's mProjExec output) and its optional area
// image (Montage's NAME_area.fits: each pixel's covered area; pixels under half of the image's
// largest area count as uncovered).
struct ProjectedInput {
  std::string image, area;
};

// The images among `paths`: a directory gives its FITS files (.fits, .fit, .fts, also .gz), in
// name order; a file NAME_area.EXT is the area image of NAME.EXT when that exists (and is not an
// image of its own), and NAME.EXT takes it. Throws InputError for a missing path or a directory
// without FITS images, UsageError when nothing is left.
std::vector<ProjectedInput> projected_inputs(const std::vector<std::string>& paths);

struct ProjectedOptions {
  std::filesystem::path header;  // the template (Montage's form: KEY = value lines): the output's grid and WCS
  // Fit each image's smooth background (plane + radial term in its own pixels) to the overlaps and
  // take it off as the image is read (gdp sky's plate fit: damped, robust; docs/sky.md).
  bool fit_backgrounds = true;
  double background_damping = 1e-3;
  bool graphcut_seams = false;  // gdp blend's graph-cut seams (on the levelled images), not its depth seams
  std::function<void(const std::string&)> note;  // the fit's summary line
};

struct ProjectedSummary {
  int width = 0, height = 0;    // the template's
  std::vector<double> offsets;  // per image: the constant taken off it, from its overlaps (mean 0)
  // Per image with fit_backgrounds: its level (as `offsets`) and the smooth terms taken off (slope
  // u, slope v, radial, in sky/plate_backgrounds.h's basis of its rectangle), and their rms over
  // the image; else empty.
  std::vector<std::array<double, 4>> backgrounds;
  std::vector<double> background_rms;
  long long covered = 0;        // output pixels with a value
  double seconds_offsets = 0.0;
  BlendReport blend;            // seams and solve
};

// Places every image on the template by its WCS (a whole-pixel shift: same projection, scale and
// rotation to 1e-6, offsets whole to 1e-3 pixel), takes each image's smooth background (with
// fit_backgrounds) and constant level against its overlaps off (least squares on the overlap
// graph: constant differences vanish exactly),
// chooses seams by depth or graph cut (gdp blend's), solves the planar gradient-domain stitch and writes `out`
// on the template's grid, one channel, the template's cards in FITS headers, NaN where no image
// covers a pixel. Streams like gdp blend: rows of the images crossing the current row.
// Throws InputError naming the file (no WCS, another grid, not one 2-D image, an image that
// overlaps no other, outside the template), UsageError, OutputError.
void sky_projected(const std::vector<ProjectedInput>& inputs, const ProjectedOptions& options,
                   const SolverOptions& solver, const std::filesystem::path& out, WriteOptions write,
                   ProjectedSummary* summary = nullptr);

}  // namespace gdp
