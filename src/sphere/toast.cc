// The exact recursive TOAST map between the square and the sphere, forward and inverse.
#include <array>

#include "sphere/octant.h"
#include "sphere/vec3.h"

namespace gdp::sphere {

namespace {

using Tri = std::array<Vec3, 3>;

// The four children of a subdivided triangle, each ordered so that child vertex k plays parent
// vertex k's role: corner child k keeps vertex k, the central child has the midpoint opposite k.
Tri child(const Tri& v, const Tri& mid_opposite, int which) {
  if (which == 3) return mid_opposite;
  Tri c = mid_opposite;
  for (int k = 0; k < 3; ++k) c[k] = k == which ? v[k] : mid_opposite[3 - which - k];
  return c;
}

Tri midpoints_opposite(const Tri& v) { return {midpoint(v[1], v[2]), midpoint(v[2], v[0]), midpoint(v[0], v[1])}; }

}  // namespace

Vec3 toast_to_sphere(double s, double t) {
  const Octant o = octant_of_square(s, t);
  Tri v = o.vertices;
  std::array<double, 3> w = o.weights;
  for (int level = 0; level < 48; ++level) {
    for (int k = 0; k < 3; ++k)
      if (w[k] == 1.0) return v[k];
    const Tri m = midpoints_opposite(v);
    int which = 3;
    for (int k = 0; k < 3; ++k)
      if (w[k] >= 0.5) which = k;
    if (which == 3) {
      for (double& x : w) x = 1.0 - 2.0 * x;
    } else {
      for (int k = 0; k < 3; ++k) w[k] = k == which ? 2.0 * w[k] - 1.0 : 2.0 * w[k];
    }
    v = child(v, m, which);
  }
  return normalise(w[0] * v[0] + w[1] * v[1] + w[2] * v[2]);
}

Point2 toast_from_sphere(const Vec3& p_in, int depth) {
  const Vec3 p = normalise(p_in);
  const Octant o = octant_of_direction(p);
  Tri v = o.vertices;
  const double sigma = orient(v[0], v[1], v[2]) > 0 ? 1.0 : -1.0;
  std::array<unsigned char, 64> path{};
  depth = std::max(0, std::min(depth, 64));
  for (int level = 0; level < depth; ++level) {
    const Tri m = midpoints_opposite(v);
    // Corner child k is cut off by the great circle through the two midpoints next to vertex k.
    int which = 3;
    if (sigma * orient(m[2], m[1], p) >= 0) which = 0;
    else if (sigma * orient(m[0], m[2], p) >= 0) which = 1;
    else if (sigma * orient(m[1], m[0], p) >= 0) which = 2;
    path[level] = static_cast<unsigned char>(which);
    v = child(v, m, which);
  }
  // Barycentric weights of the ray through p on the plane of the last (small) triangle.
  const Vec3 e1 = v[1] - v[0], e2 = v[2] - v[0];
  const Vec3 n = cross(e1, e2);
  const double nn = dot(n, n);
  std::array<double, 3> w{1.0, 0.0, 0.0};
  if (nn > 0.0) {
    const Vec3 q = (dot(v[0], n) / dot(p, n)) * p;
    const Vec3 d = q - v[0];
    w[1] = dot(cross(d, e2), n) / nn;
    w[2] = dot(cross(e1, d), n) / nn;
    w[0] = 1.0 - w[1] - w[2];
  }
  // Back up the path: undo each level's rescaling of the weights.
  for (int level = depth - 1; level >= 0; --level) {
    const int which = path[level];
    if (which == 3) {
      for (double& x : w) x = 0.5 * (1.0 - x);
    } else {
      for (int k = 0; k < 3; ++k) w[k] = k == which ? 0.5 * (1.0 + w[k]) : 0.5 * w[k];
    }
  }
  return square_of_octant_weights(o, w);
}

}  // namespace gdp::sphere
