// The equal-area octahedral map between the square and the sphere, and map dispatch.
#include <cmath>
#include <numbers>

#include "gdp/errors.h"
#include "sphere/octant.h"
#include "sphere/vec3.h"

namespace gdp::sphere {

// In an octant with flat weights (w0, w1, w2) on (pole, X, Y), r = w1 + w2 is the L1 distance
// from the pole. The cap r' <= r has square area r^2 / 2 and sphere area (pi/2)(1 - cos theta), so
// cos theta = 1 - r^2 keeps areas; longitude within the octant is (pi/2) w2 / r, linear along
// each diamond |s| + |t| = const, which keeps areas between meridians too.
Vec3 octahedral_to_sphere(double s, double t) {
  const Octant o = octant_of_square(s, t);
  const double r = o.weights[1] + o.weights[2];
  if (r <= 0.0) return o.vertices[0];
  const double phi = 0.5 * std::numbers::pi * o.weights[2] / r;
  const double sin_theta = r * std::sqrt(std::max(0.0, 2.0 - r * r));
  const double z = 1.0 - r * r;
  return {o.sx * sin_theta * std::cos(phi), o.sy * sin_theta * std::sin(phi), o.north ? z : -z};
}

Point2 octahedral_from_sphere(const Vec3& p_in) {
  const Vec3 p = normalise(p_in);
  const Octant o = octant_of_direction(p);
  const double rho2 = p.x * p.x + p.y * p.y;
  const double r = std::sqrt(rho2 / (1.0 + std::abs(p.z)));  // r^2 = 1 - |z|, without cancellation
  const double phi = std::atan2(std::abs(p.y), std::abs(p.x));
  const double w2 = r * phi / (0.5 * std::numbers::pi);
  return square_of_octant_weights(o, {1.0 - r, r - w2, w2});
}

SquareMap parse_square_map(const std::string& name) {
  if (name == "toast") return SquareMap::Toast;
  if (name == "octahedral") return SquareMap::Octahedral;
  throw UsageError("unknown sphere map '" + name + "' (toast or octahedral)");
}

Vec3 square_to_sphere(SquareMap map, double s, double t) {
  return map == SquareMap::Toast ? toast_to_sphere(s, t) : octahedral_to_sphere(s, t);
}

Point2 square_from_sphere(SquareMap map, const Vec3& p) {
  return map == SquareMap::Toast ? toast_from_sphere(p) : octahedral_from_sphere(p);
}

}  // namespace gdp::sphere
