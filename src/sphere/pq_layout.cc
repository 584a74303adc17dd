// The periodic-quincuncial layout: PQ pixels <-> square pixels, directions, the index map.
#include <cmath>
#include <vector>

#include "gdp/errors.h"
#include "sphere/vec3.h"
#include "topology/spherical.h"

namespace gdp::sphere {

std::array<int, 2> pq_wrap(int height, int i, int j) {
  const auto [ii, jj] = topology::Spherical().map(i, j, 4 * height, height);
  return {ii, jj};
}

std::array<int, 2> pq_to_square_pixel(int height, int i, int j) {
  const int w = 4 * height;
  if (i < w / 2) return {i, j + height};
  return {w - 1 - i, height - 1 - j};
}

Vec3 pq_pixel_direction(SquareMap map, int height, int i, int j) {
  const auto [c, r] = pq_to_square_pixel(height, i, j);
  const double n = 2.0 * height;
  return square_to_sphere(map, (2.0 * c + 1.0) / n - 1.0, 1.0 - (2.0 * r + 1.0) / n);
}

Point2 pq_from_direction(SquareMap map, int height, const Vec3& p, int toast_depth) {
  const Point2 st = map == SquareMap::Toast ? toast_from_sphere(p, toast_depth) : octahedral_from_sphere(p);
  const double n = 2.0 * height, w = 4.0 * height;
  const double u = (st.x + 1.0) * 0.5 * n;  // square column coordinate, 0 .. n
  const double v = (1.0 - st.y) * 0.5 * n;  // square row coordinate, 0 .. n
  if (v >= height) return {u, v - height};   // bottom half: left half of the PQ image
  return {w - u, height - v};                // top half rotated by 180 degrees: right half
}

void pq_row(SquareMap map, int height, int j, std::span<Vec3> out) {
  const int w = 4 * height;
  if (height < 1 || j < -1 || j > height || static_cast<int>(out.size()) != w)
    throw UsageError("pq_row: row " + std::to_string(j) + " of a PQ image of height " + std::to_string(height));
  if (j == -1 || j == height) {
    const int inside = j == -1 ? 0 : height - 1;
    std::vector<Vec3> row(w);
    pq_row(map, height, inside, row);
    for (int i = 0; i < w; ++i) out[i] = row[pq_wrap(height, i, j)[0]];
    return;
  }
  // The left half is square row j + H; the right half is square row H - 1 - j reversed, which is
  // row j + H mirrored in t (both maps are symmetric under y -> -y, exactly in floating point).
  const int n = 2 * height;
  square_row(map, n, j + height, out.first(n));
  for (int i = n; i < w; ++i) {
    const Vec3& v = out[w - 1 - i];
    out[i] = {v.x, -v.y, v.z};
  }
}

int default_pq_height(long long source_pixels) {
  const double h = std::sqrt(std::max(1.0, double(source_pixels)) / 4.0);
  if (h <= 16.0) return std::max(2, 2 * static_cast<int>(std::lround(h / 2.0)));  // the solver needs H even
  int k = 0;
  while (h / double(1LL << (k + 1)) >= 8.0) ++k;
  const long long m = std::min(16LL, std::max(8LL, std::llround(h / double(1LL << k))));
  return static_cast<int>(m << k);
}

}  // namespace gdp::sphere
