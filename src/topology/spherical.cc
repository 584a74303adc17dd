// Spherical (PQ) topology: the index map of NUMERICS.md §4 and the sizes it admits.
#include "topology/spherical.h"

#include <fmt/format.h>

#include "gdp/errors.h"

namespace gdp::topology {

// Row -1 - j is row j mirrored about column 0 (i -> W-1-i); row 2H-1-j is row j mirrored about
// column W/2 (i -> W/2-1-i, modulo W). Both are 180-degree rotations of the plane about a
// point of the domain's edge, so neighbours of neighbours come out right as well.
std::pair<int, int> Spherical::map(int i, int j, int w, int h) const {
  i = fem::wrap_index(i, w);
  while (j < 0 || j >= h) {
    if (j < 0) {
      i = w - 1 - i;
      j = -1 - j;
    } else {
      i = fem::wrap_index(w / 2 - 1 - i, w);
      j = 2 * h - 1 - j;
    }
  }
  return {i, j};
}

void Spherical::validate_size(int w, int h) const {
  if (h < 2 || h % 2 != 0 || w != 4 * h)
    throw UsageError(fmt::format(
        "a spherical (PQ) image must be 4H x H with H even (H = m * 2^k with small m solves fastest), got {}x{}", w,
        h));
}

std::pair<int, int> Spherical::coarse_size(const fem::Axis& x, const fem::Axis& y) const {
  const int mh = fem::next_size(y);
  if (mh == y.n) return {x.n, y.n};
  return {x.n / 2, mh};
}

}  // namespace gdp::topology
