// Seams between sky plates: each point of the sphere takes the plate it lies deepest inside.
#pragma once

#include <span>

namespace gdp::sky {

// Where a point falls in one plate: its pixel coordinates there and whether the plate has a
// value (inside it and not blank).
struct PlateHit {
  int plate = -1;
  double x = 0.0, y = 0.0;
  bool valid = false;
};

// How deep (x, y) lies inside a w x h plate: the distance to its nearest edge in the plate's own
// pixels (<= 0 outside). Cheap and monotone, so neighbouring points mostly agree and seams are
// the plates' medial lines (a Voronoi-like partition of the overlaps).
double depth_inside(double x, double y, int w, int h);

// The index into `hits` of the plate the point takes (the valid hit of greatest depth, which
// is negative outside every plate: the nearest plate's extension; the earlier plate on ties),
// or -1 when no hit is valid. `sizes` gives each plate's
// width and height as {w0, h0, w1, h1, ...} indexed by PlateHit::plate. `preferred` (a plate
// index, or -1): where the point lies inside that plate (not its extension) and another plate's
// hit is valid too, it is taken (a star's
// disk given to one plate, seam_sources.h).
int choose_plate(std::span<const PlateHit> hits, std::span<const int> sizes, int preferred = -1);

}  // namespace gdp::sky
