// Octant selection and the fold of the square's south triangles onto the octahedron.
#include "sphere/octant.h"

#include <cmath>

namespace gdp::sphere {

namespace {

Octant make(bool north, double sx, double sy) {
  Octant o;
  o.north = north;
  o.sx = sx;
  o.sy = sy;
  o.vertices = {Vec3{0.0, 0.0, north ? 1.0 : -1.0}, Vec3{sx, 0.0, 0.0}, Vec3{0.0, sy, 0.0}};
  return o;
}

}  // namespace

Octant octant_of_square(double s, double t) {
  const double a = std::abs(s), b = std::abs(t);
  const bool north = a + b <= 1.0;
  Octant o = make(north, s < 0 ? -1.0 : 1.0, t < 0 ? -1.0 : 1.0);
  if (north) o.weights = {1.0 - a - b, a, b};
  else o.weights = {a + b - 1.0, 1.0 - b, 1.0 - a};
  return o;
}

Octant octant_of_direction(const Vec3& p) {
  return make(p.z >= 0.0, p.x < 0 ? -1.0 : 1.0, p.y < 0 ? -1.0 : 1.0);
}

Point2 square_of_octant_weights(const Octant& o, const std::array<double, 3>& w) {
  double a = 0.0, b = 0.0;
  if (o.north) {
    a = w[1];
    b = w[2];
  } else {
    a = 1.0 - w[2];
    b = 1.0 - w[1];
  }
  a = std::min(1.0, std::max(0.0, a));
  b = std::min(1.0, std::max(0.0, b));
  return {o.sx * a, o.sy * b};
}

}  // namespace gdp::sphere
