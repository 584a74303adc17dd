// Graph-cut seams: the depth seams moved through the overlaps to where the layers agree best.
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <vector>

#include "blend/seam_grid.h"
#include "blend/seams.h"

namespace gdp::blending {

struct GraphcutOptions {
  int scale = 0;  // the coarse grid's cell size in pixels (0: min(W, H) / 128, clamped to 1..8)
  int threads = 1;  // workers of the depth seams it starts from (the same labels on any number)
};

// The layers the graph cut reads, a window of rows at a time: gdp blend's canvas (LayerWindow)
// or gdp sky's PQ rows (sky/pq_graphcut.h). A pass slides a window down the grid from the top;
// restart() begins the next pass.
class SeamLayers {
 public:
  virtual ~SeamLayers() = default;
  virtual int width() const = 0;
  virtual int height() const = 0;
  virtual int channels() const = 0;
  virtual void restart() = 0;
  // Rows [top, bottom) held; both only grow within a pass.
  virtual void slide(int top, int bottom) = 0;
  // Per layer: its Patch over the window's rows (absolute rows), null where it has none there;
  // a cell it covers may be chosen for it, its colour there is what the seam cost compares.
  virtual const std::vector<const Patch*>& layers() const = 0;
  // SeamGrid::uncovered; asked after the first pass.
  virtual double uncovered_cost() const = 0;
};

// A graph cut's labels and the seam costs (grid_cost, over the whole grid) of the depth labels it
// started from and of its own; `labels` null where the cut cost more than the depth labels (it
// does not in practice; the check is cheap): keep those.
struct GraphcutLabels {
  std::unique_ptr<LabelPlane> labels;
  double depth_cost = 0, cost = 0;
};

// Starting from `depth` (every pixel's label; read after the first pass over `layers`, which may
// fill it), alpha-expansion over the layers on a coarse grid (cells of `scale` pixels: a layer's
// mean colour per cell it wholly covers; held whole: about (4 x channels + 5) bytes per cell per
// layer covering it), then again at full resolution in a band of cells around the coarse seams,
// strip by strip down the grid (the layers crossing 64 + 32 rows held). Only pixels two or more
// layers cover change, each only to a layer that covers it. Two passes over `layers` (the costs are
// summed in the refinement's strips).
GraphcutLabels graphcut_labels(SeamLayers& layers, const LabelPlane& depth, bool wrap_x,
                               const std::filesystem::path& temp_dir, const std::function<void(double)>& progress,
                               const GraphcutOptions& options = {});

// Starts from compute_seams' labels and applies graphcut_labels on the canvas. The cost is
// seam_costs' (seam_grid.h). Fills SeamResult's costs.
SeamResult compute_graphcut_seams(const BlendPlan& plan, bool wrap_x, const std::filesystem::path& temp_dir,
                                  const std::function<void(double)>& progress, const GraphcutOptions& options = {});

// The seam cost of each label plane over the grid (pairs of 4-neighbours with different labels,
// pair_cost in seam_grid.h): one pass over the layers (a restart first).
std::vector<double> seam_costs(SeamLayers& layers, const std::vector<const LabelPlane*>& planes, bool wrap_x);
// The same over the canvas.
std::vector<double> seam_costs(const BlendPlan& plan, const std::vector<const LabelPlane*>& planes, bool wrap_x);

}  // namespace gdp::blending
