// A sky plate in memory: its pixels (one plane), its WCS, and where it lies on the sphere.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "gdp/sphere.h"
#include "sky/wcs.h"

namespace gdp::sky {

// Plates are extended beyond their edges by this fraction of their size (docs/sky.md).
inline constexpr double kExtension = 0.5;

struct Plate {
  std::string name;
  std::unique_ptr<Wcs> wcs;
  int width = 0, height = 0;
  std::vector<float> pixels;  // rows top down; NaN: blank
  long planes = 1;            // planes in the file (a cube: `plane` was taken)
  long plane = 0;             // the plane read (0-based)
  sphere::Vec3 centre;        // direction of the plate's centre
  double cos_radius = 1.0;    // every pixel of the plate lies within this cosine of the centre
  double cos_reach = 1.0;     // ... and its extension (half its size beyond every edge) within this
  double scale = 0.0;         // degrees per pixel at the centre (the finer axis)
  double mean = 0.0;          // of the finite pixels
  double fade_to = 0.0;       // where its extension ends (load_plate: the mean; set_fade_levels)
  std::vector<float> edge_correction;  // per border pixel, added where its extension starts (plate_extension.h)

  // The plate's value at (x, y), also beyond its edges (plate_extension.cc): inside, sample();
  // within `margin` pixels outside, the nearest edge value plus edge_correction there (compact
  // sources cut by the edge bridged over, so that they are not drawn out along the extension)
  // fading smoothly to `fade_to` (reached at 0.8 margin): an extension whose far boundary is one
  // constant (docs/sky.md).
  float extended(double x, double y, double margin) const;

  // Value at gdp pixel coordinates (x, y): Catmull-Rom cubic where the 4 x 4 pixel centres
  // around it are finite, else bilinear between the finite ones (interpolate.h; indices clamped
  // to the plate); NaN where all four nearest are blank.
  float sample(double x, double y) const;
  // Whether sample(x, y) is finite (cheaper).
  bool has_value(double x, double y) const;
};

// Reads the header of the first image HDU of `path`: its size, WCS and footprint; no pixels
// (read_pixels). Throws InputError naming the file: not FITS, no celestial WCS, a WCS wcslib
// rejects, plane (0-based) out of range.
Plate open_plate(const std::string& path, long plane = 0);

// Reads an opened plate's plane into its pixels and sets its mean. Throws InputError naming the
// file when every pixel is blank or the file cannot be read.
void read_pixels(Plate& plate);

// open_plate and read_pixels.
Plate load_plate(const std::string& path, long plane = 0);

// Points along the four sides of [left, right] x [top, bottom] (pixel coordinates), every
// 1/steps of a side, corners included.
std::vector<std::array<double, 2>> border_points(double left, double top, double right, double bottom, int steps);

// A direction from longitude and latitude in degrees (z: the pole, x: longitude 0).
sphere::Vec3 direction(double lon, double lat);
// Longitude (in [0, 360)) and latitude of a direction, in degrees.
void lon_lat(const sphere::Vec3& d, double& lon, double& lat);

}  // namespace gdp::sky
