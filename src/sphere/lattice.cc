// Rows of the midpoint-subdivision lattice of a spherical triangle, built level by level.
#include "sphere/lattice.h"

#include "sphere/vec3.h"

namespace gdp::sphere {

namespace {

// Row q of level k from rows of level k - 1 (`lo` = row q/2 rounded down, `hi` = the next one).
// Even q: the row above with its edge midpoints interleaved. Odd q: midpoints of the vertical
// edges (even p) and of the diagonal edges (odd p) between the two rows above.
void refine(long long q, long long lo_index, const std::vector<Vec3>& lo, const std::vector<Vec3>& hi,
            long long side, std::vector<Vec3>& out) {
  const long long n = side - q + 1;
  out.resize(static_cast<std::size_t>(n));
  if (q % 2 == 0) {
    const std::vector<Vec3>& r = (q / 2 == lo_index) ? lo : hi;
    for (long long p = 0; p < n; ++p)
      out[p] = p % 2 == 0 ? r[p / 2] : midpoint(r[(p - 1) / 2], r[(p + 1) / 2]);
  } else {
    for (long long p = 0; p < n; ++p)
      out[p] = p % 2 == 0 ? midpoint(lo[p / 2], hi[p / 2]) : midpoint(hi[(p - 1) / 2], lo[(p + 1) / 2]);
  }
}

}  // namespace

LatticeRows lattice_rows(const Vec3& a, const Vec3& b, const Vec3& c, int level, long long q0) {
  // Level 0: row 0 = (A, B), row 1 = (C).
  std::vector<Vec3> lo{a, b}, hi{c}, next_lo, next_hi;
  long long lo_index = 0;
  for (int k = 1; k <= level; ++k) {
    const long long side = 1LL << k;
    const long long want = q0 >> (level - k);  // rows want and want + 1 are needed at level k
    refine(want, lo_index, lo, hi, side, next_lo);
    const bool has_hi = want + 1 <= side;
    if (has_hi) refine(want + 1, lo_index, lo, hi, side, next_hi);
    else next_hi.clear();
    lo.swap(next_lo);
    hi.swap(next_hi);
    lo_index = want;
  }
  return {std::move(lo), std::move(hi)};
}

}  // namespace gdp::sphere
