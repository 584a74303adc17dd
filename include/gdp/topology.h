// The domain topologies an image can live on.
#pragma once

#include <string_view>

namespace gdp {

enum class Domain {
  Planar,       // Neumann boundaries on all four sides
  Cylindrical,  // periodic left/right (a 360-degree panorama), Neumann top/bottom
  Spherical,    // the periodic-quincuncial (PQ) rectangle, W = 4H: periodic left/right, top and
                // bottom edges folded onto themselves (docs/sphere-solver.md)
};

// Parses "planar" / "cylindrical" / "spherical" (or "pq"); throws UsageError otherwise.
Domain parse_domain(std::string_view name);

}  // namespace gdp
