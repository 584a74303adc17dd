// Levels of images placed on one canvas: each image's constant against its overlaps, from every pixel two images cover.
#pragma once

#include <vector>

#include "gdp/blend.h"

namespace gdp::sky {

struct CanvasLevels {
  std::vector<double> offsets;  // per layer: o_k, o_a - o_b fitting mean(a - b) (offsets_from_overlaps)
  std::vector<char> overlapped;  // per layer: some pixel of it is covered by another layer too
};

// Reads every layer of `plan` once, top to bottom (a row of each layer crossing the current canvas
// row at a time), summing a - b over the pixels each pair covers (colour channel 0).
CanvasLevels canvas_levels(const BlendPlan& plan);

}  // namespace gdp::sky
