// Planar topology: Neumann (half-sample reflective) boundaries on all four sides.
#include "topology/planar.h"

#include <fmt/format.h>

#include "gdp/errors.h"

namespace gdp::topology {

std::pair<int, int> Planar::map(int i, int j, int w, int h) const {
  return {fem::reflect_index(i, w), fem::reflect_index(j, h)};
}

void Planar::validate_size(int w, int h) const {
  if (w < 1 || h < 1) throw UsageError(fmt::format("planar domain needs a non-empty image, got {}x{}", w, h));
}

}  // namespace gdp::topology
