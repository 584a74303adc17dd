// Where an image already reprojected onto a template lies on it: a whole-pixel shift, checked against both WCS.
#pragma once

#include <string>

#include "gdp/blend.h"
#include "gdp/sky_projected.h"
#include "sky/wcs.h"

namespace gdp::sky {

// The template pixel (x, y) of the image's pixel (0, 0) (gdp's pixels: rows top down). Throws
// InputError "`name`: ..." unless `image` is `tpl` shifted by whole pixels: the same projection
// and frame, pixel axes that map to the template's to 1e-6 (scale, rotation), one shift over the
// whole image to 1e-3 pixel (CRVAL, the projection's parameters), and that shift whole to 1e-3.
struct Shift {
  long long x = 0, y = 0;
};
Shift place_on_template(const Wcs& image, const Wcs& tpl, const std::string& name);

// The largest finite value of a one-plane FITS image (read row by row); InputError naming the
// file when none is positive.
double largest_value(const std::string& path);

// The blend layer of an input: placed by its WCS, with its area image (if any) as the coverage
// mask, scaled so that half the image's largest area is the threshold. InputError naming the
// file: unreadable, no WCS, not on the template's grid, more than one plane.
LayerSource projected_layer(const ProjectedInput& input, const Wcs& tpl);

}  // namespace gdp::sky
