// Graph-cut seams on the sky's PQ rows: gdp blend's graph cut over the plates' levelled values.
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <vector>

#include "sky/plate.h"
#include "sky/plate_sweep.h"
#include "sky/pq_window.h"
#include "sky/seam_sources.h"

namespace gdp::blending {
class LabelPlane;
}

namespace gdp::sky {

struct PqSeams {
  std::unique_ptr<blending::LabelPlane> labels;  // the window's size: 1 + the plate, 0 where none reaches
  double depth_cost = 0, cost = 0;               // the seam cost of the distance seams and of `labels`
};

// The seams of gdp sky --seams graphcut on `window` (docs/sky.md, "Graph-cut seams"):
// blending::graphcut_labels over the PQ rows (MosaicRows), starting from the distance seams
// (with `stars`: around the stars). A layer is a plate where it has a value, less its level
// (fade_to: its fitted offset, its background already off), so the cost is the plates'
// disagreement after the fit; inside a star's disk only that star's plate counts as covering (the
// star stays whole); a pixel only one plate covers keeps that plate. Rows wrap when the window is
// the whole PQ image. Two passes over the rows (the first writes the distance labels), each
// holding the plates crossing the current rows (`pixels`; all released after each pass); the
// labels and distance labels in scratch (2 bytes a pixel each, under `temp_dir`), the coarse grid
// held whole (blend/graphcut_seams.h). The plates must be levelled (plate_passes.h) first.
PqSeams graphcut_pq_seams(std::vector<Plate>& plates, PlatePixels& pixels, const PqWindow& window,
                          const SeamSources* stars, const std::filesystem::path& temp_dir, std::size_t memory_limit);

}  // namespace gdp::sky
