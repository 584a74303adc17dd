// Rows of the midpoint-subdivision lattice of a spherical triangle (internal).
#pragma once

#include <vector>

#include "gdp/sphere.h"

namespace gdp::sphere {

// Vertices of rows q0 and q0 + 1 of the level-`level` subdivision of the spherical triangle
// (A, B, C): vertex (p, q) is where the flat weights (1 - (p + q)/2^L, p/2^L, q/2^L) land, for
// p = 0 .. 2^L - q. Computed level by level from at most two rows of the level above, so a row
// costs about four midpoints per vertex instead of a recursion per vertex.
struct LatticeRows {
  std::vector<Vec3> row0, row1;  // row1 is empty when q0 + 1 > 2^L
};
LatticeRows lattice_rows(const Vec3& a, const Vec3& b, const Vec3& c, int level, long long q0);

}  // namespace gdp::sphere
