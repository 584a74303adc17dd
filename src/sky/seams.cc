// The "deepest inside" seam rule: distance to the plate's edge in its own pixel grid.
#include "sky/seams.h"

#include <algorithm>

namespace gdp::sky {

double depth_inside(double x, double y, int w, int h) { return std::min({x, w - x, y, h - y}); }

int choose_plate(std::span<const PlateHit> hits, std::span<const int> sizes, int preferred) {
  int best = -1, valid = 0, wanted = -1;
  double deepest = 0.0;
  for (std::size_t k = 0; k < hits.size(); ++k) {
    const PlateHit& hit = hits[k];
    if (!hit.valid) continue;
    const double d = depth_inside(hit.x, hit.y, sizes[2 * hit.plate], sizes[2 * hit.plate + 1]);
    ++valid;
    if (hit.plate == preferred && d > 0.0) wanted = static_cast<int>(k);  // inside it, not its extension
    if (best < 0 || d > deepest) {
      best = static_cast<int>(k);
      deepest = d;
    }
  }
  return wanted >= 0 && valid >= 2 ? wanted : best;
}

}  // namespace gdp::sky
