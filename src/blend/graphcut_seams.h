// Graph-cut seams: the depth seams moved through the overlaps to where the layers agree best.
#pragma once

#include <filesystem>
#include <functional>
#include <vector>

#include "blend/seams.h"

namespace gdp::blending {

struct GraphcutOptions {
  int scale = 0;  // the coarse grid's cell size in pixels (0: min(W, H) / 128, clamped to 1..8)
  int threads = 1;  // workers of the depth seams it starts from (the same labels on any number)
};

// Starts from compute_seams' labels; alpha-expansion over the layers on a coarse grid of the
// canvas (cells of `scale` pixels: a layer's mean colour per cell it wholly covers), then again
// at full resolution in a band of cells around the coarse seams, strip by strip down the canvas.
// The cost is seam_costs' (seam_grid.h). If the result cost more than the depth seams (it does
// not in practice; the check is cheap) the depth seams are kept. Fills SeamResult's costs.
SeamResult compute_graphcut_seams(const BlendPlan& plan, bool wrap_x, const std::filesystem::path& temp_dir,
                                  const std::function<void(double)>& progress, const GraphcutOptions& options = {});

// The seam cost of each label plane over the canvas (pairs of 4-neighbours with different
// labels, pair_cost in seam_grid.h): one streamed pass over the layers.
std::vector<double> seam_costs(const BlendPlan& plan, const std::vector<const LabelPlane*>& planes, bool wrap_x);

}  // namespace gdp::blending
