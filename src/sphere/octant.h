// The octahedron's eight octants: which one a square point or a direction lies in (internal).
#pragma once

#include <array>

#include "gdp/sphere.h"

namespace gdp::sphere {

// An octant as the spherical triangle (pole, X, Y) with X = (sx, 0, 0), Y = (0, sy, 0). A square
// point's flat barycentric weights on it are (1 - a - b, a, b) in the north (a = |s|, b = |t|,
// a + b <= 1) and (a + b - 1, 1 - b, 1 - a) in the south, where the square is folded.
struct Octant {
  std::array<Vec3, 3> vertices;
  std::array<double, 3> weights{};  // of the square point (octant_of_square only)
  double sx = 1.0, sy = 1.0;
  bool north = true;
};

Octant octant_of_square(double s, double t);
Octant octant_of_direction(const Vec3& p);
// The square point (s, t) with the given weights on octant `o`.
Point2 square_of_octant_weights(const Octant& o, const std::array<double, 3>& w);

}  // namespace gdp::sphere
