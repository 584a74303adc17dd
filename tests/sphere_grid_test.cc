// Fast whole-row generation against the per-point maps; the PQ layout and its index map.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "gdp/sphere.h"

namespace gdp::sphere {
namespace {

double dist(const Vec3& a, const Vec3& b) { return std::hypot(a.x - b.x, a.y - b.y, a.z - b.z); }

double worst_row_error(SquareMap map, int n) {
  double worst = 0.0;
  std::vector<Vec3> row(n);
  for (int r = 0; r < n; ++r) {
    square_row(map, n, r, row);
    for (int c = 0; c < n; ++c) {
      const Vec3 p = square_to_sphere(map, (2.0 * c + 1.0) / n - 1.0, 1.0 - (2.0 * r + 1.0) / n);
      worst = std::max(worst, dist(row[c], p));
    }
  }
  return worst;
}

TEST(SphereGrid, ToastRowsExactForPowersOfTwo) {
  for (int n : {2, 4, 8, 64, 256}) EXPECT_LT(worst_row_error(SquareMap::Toast, n), 2e-15) << n;
}

// Other sizes interpolate in the lattice one level finer than the pixels: the error falls as
// 1/n^2 (a thousandth of a pixel at n = 3, 3e-11 radians at n = 2816).
TEST(SphereGrid, ToastRowsCloseForOtherSizes) {
  for (int n : {3, 6, 10, 22, 96, 176}) EXPECT_LT(worst_row_error(SquareMap::Toast, n) * n * n, 2e-3) << n;
}

TEST(SphereGrid, OctahedralRows) { EXPECT_LT(worst_row_error(SquareMap::Octahedral, 40), 1e-15); }

TEST(SphereGrid, PqLayoutMatchesSquare) {
  const int h = 6, w = 24, n = 12;
  // Left half = bottom half of the square; right half = top half rotated by 180 degrees.
  EXPECT_EQ(pq_to_square_pixel(h, 0, 0), (std::array<int, 2>{0, 6}));
  EXPECT_EQ(pq_to_square_pixel(h, 11, 5), (std::array<int, 2>{11, 11}));
  EXPECT_EQ(pq_to_square_pixel(h, 12, 0), (std::array<int, 2>{11, 5}));
  EXPECT_EQ(pq_to_square_pixel(h, 23, 5), (std::array<int, 2>{0, 0}));
  // Every square pixel is used exactly once.
  std::vector<int> used(n * n, 0);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const auto [c, r] = pq_to_square_pixel(h, i, j);
      ++used[r * n + c];
    }
  for (int u : used) EXPECT_EQ(u, 1);
}

void expect_pq_rows_invert(SquareMap map, int h, double tol) {
  {
    const int w = 4 * h;
    std::vector<Vec3> row(w);
    for (int j = 0; j < h; ++j) {
      pq_row(map, h, j, row);
      for (int i = 0; i < w; ++i) {
        EXPECT_LT(dist(row[i], pq_pixel_direction(map, h, i, j)), tol / h);
        const Point2 c = pq_from_direction(map, h, row[i]);
        EXPECT_NEAR(c.x, i + 0.5, tol) << i << " " << j;
        EXPECT_NEAR(c.y, j + 0.5, tol) << i << " " << j;
      }
    }
  }
}

TEST(SphereGrid, PqRowsAndInverse) {
  expect_pq_rows_invert(SquareMap::Toast, 16, 1e-9);        // N = 32: exact lattice vertices
  expect_pq_rows_invert(SquareMap::Toast, 12, 1e-5);        // N = 24: interpolated
  expect_pq_rows_invert(SquareMap::Octahedral, 12, 1e-9);
}

// Neighbours across the PQ boundary (the index map) are neighbours on the sphere: the angle to
// them is about one pixel, never a jump across the image.
TEST(SphereGrid, PqIndexMapJoinsNeighboursOnTheSphere) {
  const int h = 32, w = 128;
  const double pixel = std::sqrt(std::numbers::pi) / h;  // mean pixel size, radians
  std::vector<Vec3> above(w), first(w), last(w), below(w);
  pq_row(SquareMap::Toast, h, -1, above);
  pq_row(SquareMap::Toast, h, 0, first);
  pq_row(SquareMap::Toast, h, h - 1, last);
  pq_row(SquareMap::Toast, h, h, below);
  for (int i = 0; i < w; ++i) {
    EXPECT_EQ(pq_wrap(h, i, -1), (std::array<int, 2>{w - 1 - i, 0}));
    EXPECT_LT(dist(above[i], first[i]), 2.5 * pixel) << i;
    EXPECT_LT(dist(below[i], last[i]), 2.5 * pixel) << i;
    EXPECT_LT(dist(first[i], first[(i + 1) % w]), 2.5 * pixel) << i;  // periodic in i
  }
  EXPECT_EQ(pq_wrap(h, -1, 3), (std::array<int, 2>{w - 1, 3}));
  EXPECT_EQ(pq_wrap(h, 5, h), (std::array<int, 2>{w / 2 - 1 - 5, h - 1}));
  EXPECT_EQ(pq_wrap(h, w / 2 + 5, h + 1), (std::array<int, 2>{w - 1 - 5, h - 2}));
}

TEST(SphereGrid, DefaultHeightRule) {
  EXPECT_EQ(default_pq_height(4096LL * 2048), 1408);  // 11 * 2^7, 7.9 of 8.4 megapixels
  EXPECT_EQ(default_pq_height(1024LL * 512), 352);    // 362 -> 11 * 2^5
  EXPECT_EQ(default_pq_height(512LL * 256), 176);     // 181 -> 11.3 * 2^4 -> 11 * 2^4
  EXPECT_EQ(default_pq_height(40LL * 20), 14);        // small: rounded to even
  EXPECT_EQ(default_pq_height(32LL * 16), 12);        // 11.3 -> 12: the solver needs H even
  EXPECT_EQ(default_pq_height(3), 2);
}

}  // namespace
}  // namespace gdp::sphere
