// Levels and smooth backgrounds of images placed on one canvas, from every pixel two images cover.
#pragma once

#include <vector>

#include "gdp/blend.h"
#include "sky/plate_backgrounds.h"

namespace gdp::sky {

struct CanvasLevels {
  std::vector<double> offsets;  // per layer: o_k, o_a - o_b fitting mean(a - b) (offsets_from_overlaps)
  // Per layer, with a background fit: its smooth terms (offset + plane + radial in the layer's own
  // pixels, background_basis of its rectangle; the fit's own offsets are not used); else empty.
  std::vector<PlateBackground> backgrounds;
  std::vector<char> overlapped;  // per layer: some pixel of it is covered by another layer too
};

// Reads every layer of `plan` once, top to bottom (a row of each layer crossing the current canvas
// row at a time), summing a - b over the pixels each pair covers (colour channel 0). With
// `damping` >= 0 it also samples the overlaps on a grid (about 64 x 64 points over the smallest
// layer) and fits each layer's smooth background to them as gdp sky's plates are fitted
// (fit_backgrounds: damped, robust); the levels are then those of the layers less their smooth
// terms (the overlaps' sums corrected by the smooth terms' sums over the same pixels).
CanvasLevels canvas_levels(const BlendPlan& plan, double damping = -1.0);

// What LayerSource::background takes off layer k for its fitted smooth terms (not the offset).
LayerBackground layer_background(const PlacedLayer& layer, const PlateBackground& smooth);

}  // namespace gdp::sky
