// Seams by depth: each canvas pixel takes the layer it lies deepest inside (a two-pass distance transform).
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <span>
#include <vector>

#include "blend/kept_rows.h"
#include "blend/label_plane.h"
#include "gdp/blend.h"

namespace gdp::blending {

struct SeamResult {
  std::unique_ptr<LabelPlane> labels;
  // Per layer: some pixel it covers is covered by another layer too; -1 where not known (a
  // layer reaching outside the columns computed).
  std::vector<signed char> overlaps;
  int layers_read = 0;            // layers that took part (all, unless columns were given)
  std::size_t scratch_bytes = 0;  // distances and labels kept between the passes
  // Graph-cut seams: the seam cost of the depth seams and of those returned (graphcut_seams.h).
  double depth_cost = 0, cost = 0;
};

// Depth of a covered pixel: the chamfer distance (5x5 mask: 1, sqrt 2, sqrt 5; within 2 % of
// the Euclidean) to the nearest canvas pixel the layer does not cover; the canvas's own edges
// do not count (with wrap_x, the left and right edges meet). Ties go to the earlier layer.
// Reads every layer once, top to bottom, keeping in scratch its coverage (a bit a pixel) and the
// first pass's state where each block of rows starts; the second pass runs bottom to top, a block
// at a time: the block's first-pass distances again from those, then the second pass over them,
// and writes the label plane. On `threads` workers (layers in parallel, then blocks of rows): the
// same labels as one thread's, bit for bit.
SeamResult compute_seams(const BlendPlan& plan, bool wrap_x, const std::filesystem::path& temp_dir,
                         const std::function<void(double)>& progress, int threads = 1);

// The depth seams of columns [begin, end) only, into `labels` (the canvas's size): only the layers
// whose footprints meet those columns are read, each whole (a pixel's depth in a layer depends on
// all of it), so labels there are exactly compute_seams'. `overlaps`: 1 for a layer some pixel of
// which another layer taking part covers too, 0 for one taking part with none, -1 for the others;
// the 0s are exactly the isolated layers when the columns are the canvas's, or after
// gather_overlaps over processes whose columns together are. For a process that solves only some
// columns (mpirun). With `keep`, the layers' rows decoded are kept there for the sweep (KeptRows).
struct SeamColumns {
  int layers_read = 0;
  std::size_t distance_bytes = 0;  // the first pass's scratch (coverage and states)
};
SeamColumns compute_seam_columns(const BlendPlan& plan, bool wrap_x, const std::filesystem::path& temp_dir,
                                 const std::function<void(double)>& progress, int begin, int end,
                                 LabelPlane& labels, std::vector<signed char>& overlaps, int threads = 1,
                                 KeptRows* keep = nullptr);

}  // namespace gdp::blending
