// Seams by depth: each canvas pixel takes the layer it lies deepest inside (a two-pass distance transform).
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "blend/scratch.h"
#include "gdp/blend.h"

namespace gdp::blending {

// Per canvas pixel: 0 where no layer covers it, else 1 + the index of the layer it takes.
using Label = std::uint16_t;
inline constexpr int kMaxLayers = 65535;

// The canvas's labels, a row at a time, in any order (in memory or a scratch file).
class LabelPlane {
 public:
  LabelPlane(const std::filesystem::path& dir, int width, int height);
  int width() const { return width_; }
  int height() const { return height_; }
  void write_row(int y, std::span<const Label> row);
  // Columns [begin, end) of row y into row[begin, end).
  void read_row(int y, std::span<Label> row, int begin = 0, int end = -1) const;
  std::size_t bytes() const { return scratch_.bytes(); }

 private:
  int width_, height_;
  Scratch scratch_;
};

struct SeamResult {
  std::unique_ptr<LabelPlane> labels;
  std::vector<char> overlaps;     // per layer: some pixel it covers is covered by another layer too
  std::size_t scratch_bytes = 0;  // distances and labels kept between the passes
  // Graph-cut seams: the seam cost of the depth seams and of those returned (graphcut_seams.h).
  double depth_cost = 0, cost = 0;
};

// Depth of a covered pixel: the chamfer distance (5x5 mask: 1, sqrt 2, sqrt 5; within 2 % of
// the Euclidean) to the nearest canvas pixel the layer does not cover; the canvas's own edges
// do not count (with wrap_x, the left and right edges meet). Ties go to the earlier layer.
// Reads every layer once, top to bottom, keeping each layer's first-pass distances in scratch;
// the second pass runs bottom to top and writes the label plane.
SeamResult compute_seams(const BlendPlan& plan, bool wrap_x, const std::filesystem::path& temp_dir,
                         const std::function<void(double)>& progress);

}  // namespace gdp::blending
