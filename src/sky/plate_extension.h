// A plate's extension beyond its edges: from its edge, stars cut by the edge bridged over, fading to one level.
#pragma once

#include <vector>

#include "sky/plate.h"
#include "sky/seam_sources.h"

namespace gdp::sky {

// What the plate's extension adds to its edge values: around its border ring of pixels (clockwise
// from the top-left corner), 0 but where one of its compact `sources` (seam_sources.h's
// plate_sources of it, or of the same plate in another band: a star) reaches the edge (border pixels within its radius + 2 of its peak), where it replaces the edge
// by the straight line between the pixels around the source, so that a star cut by the edge is
// not drawn out along the extension and the solve does not carry it (docs/sky.md). Empty for
// plates narrower than 2 pixels.
std::vector<float> edge_corrections(const Plate& plate, const std::vector<PlateSource>& sources);

}  // namespace gdp::sky
