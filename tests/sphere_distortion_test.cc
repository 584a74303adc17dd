// Distortion of the square maps measured on a grid: area max/min and anisotropy (NUMERICS.md §4).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "gdp/sphere.h"

namespace gdp::sphere {
namespace {

Vec3 sub(const Vec3& a, const Vec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
double dot3(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

// Spherical triangle area (Van Oosterom and Strackee).
double tri_area(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double det = a.x * (b.y * c.z - b.z * c.y) - a.y * (b.x * c.z - b.z * c.x) + a.z * (b.x * c.y - b.y * c.x);
  return 2.0 * std::abs(std::atan2(det, 1.0 + dot3(a, b) + dot3(b, c) + dot3(c, a)));
}

struct Distortion {
  double area_ratio = 0, anisotropy = 0;
};

// Singular-value ratio of the affine map from a grid triangle (param corners pa, pb, pc in units
// of the cell) onto the chord triangle (qa, qb, qc).
double anisotropy(const double pa[2], const double pb[2], const double pc[2], const Vec3& qa, const Vec3& qb,
                  const Vec3& qc) {
  const double m00 = pb[0] - pa[0], m01 = pc[0] - pa[0], m10 = pb[1] - pa[1], m11 = pc[1] - pa[1];
  const double inv_det = 1.0 / (m00 * m11 - m01 * m10);
  const double i00 = m11 * inv_det, i01 = -m01 * inv_det, i10 = -m10 * inv_det, i11 = m00 * inv_det;
  const Vec3 e1 = sub(qb, qa), e2 = sub(qc, qa);
  // J = [e1 e2] * inverse(M): columns are the derivatives along the two grid axes.
  const Vec3 j1{e1.x * i00 + e2.x * i10, e1.y * i00 + e2.y * i10, e1.z * i00 + e2.z * i10};
  const Vec3 j2{e1.x * i01 + e2.x * i11, e1.y * i01 + e2.y * i11, e1.z * i01 + e2.z * i11};
  const double g11 = dot3(j1, j1), g22 = dot3(j2, j2), g12 = dot3(j1, j2);
  const double tr = g11 + g22, det = std::max(0.0, g11 * g22 - g12 * g12);
  const double disc = std::sqrt(std::max(0.0, tr * tr / 4 - det));
  return std::sqrt((tr / 2 + disc) / (tr / 2 - disc));
}

// Over the cells of an n x n grid, each split into two triangles along the octahedron's edges:
// cell areas (spherical triangles) and the largest anisotropy of the triangles' affine maps.
Distortion measure(SquareMap map, int n) {
  std::vector<Vec3> p((n + 1) * (n + 1));
  for (int r = 0; r <= n; ++r)
    for (int c = 0; c <= n; ++c) p[r * (n + 1) + c] = square_to_sphere(map, 2.0 * c / n - 1.0, 1.0 - 2.0 * r / n);
  double lo = 1e9, hi = 0, aniso = 0;
  const double A[2] = {0, 0}, B[2] = {1, 0}, D[2] = {0, 1}, E[2] = {1, 1};
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) {
      const Vec3 &a = p[r * (n + 1) + c], &b = p[r * (n + 1) + c + 1], &d = p[(r + 1) * (n + 1) + c],
                 &e = p[(r + 1) * (n + 1) + c + 1];
      // The equator diamond runs along a -> e in the top-right and bottom-left quadrants.
      const bool main_diag = (2 * c < n) != (2 * r < n);
      double area = 0;
      if (main_diag) {
        area = tri_area(a, e, b) + tri_area(a, d, e);
        aniso = std::max({aniso, anisotropy(A, E, B, a, e, b), anisotropy(A, D, E, a, d, e)});
      } else {
        area = tri_area(a, d, b) + tri_area(b, d, e);
        aniso = std::max({aniso, anisotropy(A, D, B, a, d, b), anisotropy(B, D, E, b, d, e)});
      }
      lo = std::min(lo, area);
      hi = std::max(hi, area);
    }
  return {hi / lo, aniso};
}

TEST(SphereDistortion, GridFigures) {
  const Distortion toast = measure(SquareMap::Toast, 256), oct = measure(SquareMap::Octahedral, 256);
  std::printf("256x256 grid: TOAST area max/min %.3f, anisotropy max %.3f; equal-area octahedral %.3f, %.3f\n",
              toast.area_ratio, toast.anisotropy, oct.area_ratio, oct.anisotropy);
  EXPECT_NEAR(toast.area_ratio, 2.11, 0.05);  // NUMERICS.md: 2.11 / 2.62
  EXPECT_NEAR(toast.anisotropy, 2.62, 0.15);
  // Equal area (SphereMaps.OctahedralIsEqualArea samples it); the triangles through the corners
  // miss the cells' curved edges near the poles, by 12% at most.
  EXPECT_LT(oct.area_ratio, 1.15);
  EXPECT_NEAR(oct.anisotropy, 2.99, 0.15);    // NUMERICS.md: 1.00 / 2.99
}

}  // namespace
}  // namespace gdp::sphere
