// Rows of one image level streamed in order, with rows and columns beyond its ends resolved by the domain.
#pragma once

#include <memory>
#include <span>
#include <vector>

#include "gdp/topology.h"
#include "topology/topology.h"

namespace gdp::apps::tonemap {

// The last `keep` rows of a level of height h pushed in order y = 0, 1, ..., and rows and
// columns just beyond its ends, read through the domain's index map (topology::Topology::map):
// reflected on the plane, wrapped left/right on the cylinder and the sphere, and on a
// spherical (PQ) domain rows beyond the top and bottom read mirrored across the folds, so
// filters see the image that continues across them.
class RowWindow {
 public:
  RowWindow(Domain domain, int width, int height, int keep);
  void push(std::span<const float> row);
  int pushed() const { return pushed_; }
  int width() const { return width_; }
  int height() const { return height_; }
  // Column i of a row, i at most a few pixels outside [0, width).
  int column(int i) const { return i >= 0 && i < width_ ? i : topology_->map(i, 0, width_, height_).first; }
  // Row y: one of the last `keep` pushed, or beyond an end and reflecting to one of them. The
  // span stays valid until the next push or until four more ghost rows have been asked for.
  std::span<const float> row(int y);

 private:
  std::span<const float> held(int y) const;

  std::unique_ptr<topology::Topology> topology_;
  int width_, height_, keep_, pushed_ = 0;
  std::vector<std::vector<float>> ring_;
  std::vector<float> ghosts_[4];
  int next_ghost_ = 0;
};

}  // namespace gdp::apps::tonemap
