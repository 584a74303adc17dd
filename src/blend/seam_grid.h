// Labels on a grid of cells with the layers' colours there: the seam cost and its alpha-expansion (Boost's Boykov-Kolmogorov max-flow).
#pragma once

#include <vector>

#include "blend/seams.h"

namespace gdp::blending {

// A layer's samples on part of a grid (coarse cells or canvas rows): which cells it covers and its
// colour there (channels interleaved per cell). Rows are absolute (canvas or coarse rows).
struct Patch {
  int x0 = 0, y0 = 0, w = 0, h = 0;
  std::vector<float> colour;
  std::vector<unsigned char> covers;
  bool has(int x, int y) const {
    return x >= x0 && x < x0 + w && y >= y0 && y < y0 + h && covers[static_cast<std::size_t>(y - y0) * w + (x - x0)];
  }
  const float* at(int x, int y, int channels) const {
    return colour.data() + (static_cast<std::size_t>(y - y0) * w + (x - x0)) * channels;
  }
};

// Rows [row0, row0 + height) of a grid `width` cells wide; `layers[k]` is layer k's patch there
// (null: it has none). labels: 0 = none, else 1 + the layer (as the label plane); only `free`
// cells may change, and only to a layer that covers them.
struct SeamGrid {
  int width = 0, height = 0, row0 = 0, channels = 1;
  // The cost of a cell for a label whose layer does not cover it (cell_cost): the largest
  // difference of the layers' values (blend: `channels`, its values lying in [0, 1]).
  double uncovered = 1.0;
  bool wrap_x = false;
  std::vector<const Patch*> layers;
  std::vector<Label> labels;
  std::vector<unsigned char> free;
  Label& label(int x, int r) { return labels[static_cast<std::size_t>(r) * width + x]; }
  Label label(int x, int r) const { return labels[static_cast<std::size_t>(r) * width + x]; }
};

// The seam cost of a cell for labels a, b (1 + layer): the colour difference of the two layers
// there (sum over channels of |A - B|) where both cover it, else `uncovered`. The cost of two 4-neighbours labelled a != b (neither 0) is the
// sum of that at both cells (Kwatra et al. 2003): a metric in the labels, so alpha-expansion
// applies.
double cell_cost(const SeamGrid& g, int x, int r, Label a, Label b);
double pair_cost(const SeamGrid& g, int x0, int r0, int x1, int r1, Label a, Label b);

// The seam cost of grid rows [begin, end): pairs within those rows and each with the row above it
// (from row max(begin, 1)).
double grid_cost(const SeamGrid& g, int begin, int end);

// Alpha-expansion (Boykov, Veksler and Zabih 2001) over the free cells: each layer in turn may
// take any set of free cells it covers, by a minimum cut; sweeps until no move lowers the cost
// (at most `sweeps`). Returns the number of cells that changed.
long expand_labels(SeamGrid& g, int sweeps = 4);

}  // namespace gdp::blending
