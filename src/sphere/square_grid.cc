// Whole rows of square pixel centres mapped to the sphere, fast (no recursion per pixel).
#include <cmath>

#include "gdp/errors.h"
#include "sphere/lattice.h"
#include "sphere/vec3.h"

namespace gdp::sphere {

namespace {

// Pixel centres are at lattice coordinates num / n (numerators are integers); the lattice level
// is log2(n) for powers of two (centres are then lattice vertices) and otherwise one level finer
// than the pixels, interpolating in the lattice triangle holding the centre.
int lattice_level(long long n) {
  int level = 1;
  while ((1LL << level) < n) ++level;
  return (1LL << level) == n ? level : level + 1;
}

// Normalised barycentric interpolation at lattice point (p_num / n, q / n) between rows q0 = q
// rounded down (r0) and q0 + 1 (r1).
Vec3 interpolate(const LatticeRows& rows, long long p_num, long long q_num, long long n) {
  const long long p0 = p_num / n, q_rem = q_num % n, p_rem = p_num % n;
  if (p_rem == 0 && q_rem == 0) return rows.row0[p0];
  const double fp = double(p_rem) / n, fq = double(q_rem) / n;
  const auto& r0 = rows.row0;
  const auto& r1 = rows.row1;
  if (fp + fq <= 1.0) {
    const Vec3 right = p_rem ? r0[p0 + 1] : r0[p0];
    const Vec3 up = q_rem ? r1[p0] : r0[p0];
    return normalise((1.0 - fp - fq) * r0[p0] + fp * right + fq * up);
  }
  return normalise((fp + fq - 1.0) * r1[p0 + 1] + (1.0 - fq) * r0[p0 + 1] + (1.0 - fp) * r1[p0]);
}

void toast_row(long long n, int row, std::span<Vec3> out) {
  const int level = lattice_level(n);
  const long long side = 1LL << level, full = n * side;
  const long long q_num = std::llabs(n - 2LL * row - 1) * side;  // b * 2^L * n
  const Vec3 pole_n{0, 0, 1}, pole_s{0, 0, -1}, x{1, 0, 0}, y{0, 1, 0};
  // First quadrant only; the other three are reflections (exact in floating point).
  const LatticeRows north = lattice_rows(pole_n, x, y, level, q_num / n);
  const LatticeRows south = lattice_rows(pole_s, y, x, level, (full - q_num) / n);
  const double sy = 2LL * row + 1 > n ? -1.0 : 1.0;
  for (long long c = 0; c < n; ++c) {
    const long long p_num = std::llabs(2 * c + 1 - n) * side;
    Vec3 v = p_num + q_num <= full ? interpolate(north, p_num, q_num, n)
                                   : interpolate(south, full - p_num, full - q_num, n);
    if (2 * c + 1 < n) v.x = -v.x;
    v.y *= sy;
    out[c] = v;
  }
}

}  // namespace

void square_row(SquareMap map, int n, int row, std::span<Vec3> out) {
  if (n < 1 || row < 0 || row >= n || static_cast<long long>(out.size()) != n)
    throw UsageError("square_row: row " + std::to_string(row) + " of a " + std::to_string(n) + " square");
  if (map == SquareMap::Toast) return toast_row(n, row, out);
  const double t = 1.0 - (2.0 * row + 1.0) / n;
  for (int c = 0; c < n; ++c) out[c] = octahedral_to_sphere((2.0 * c + 1.0) / n - 1.0, t);
}

}  // namespace gdp::sphere
