// Cylindrical topology: wrap-around columns, reflective rows.
#include "topology/cylindrical.h"

#include <fmt/format.h>

#include "gdp/errors.h"

namespace gdp::topology {

std::pair<int, int> Cylindrical::map(int i, int j, int w, int h) const {
  return {fem::wrap_index(i, w), fem::reflect_index(j, h)};
}

void Cylindrical::validate_size(int w, int h) const {
  if (w < 3 || h < 1)
    throw UsageError(fmt::format("cylindrical domain needs at least 3 columns, got {}x{}", w, h));
}

}  // namespace gdp::topology
