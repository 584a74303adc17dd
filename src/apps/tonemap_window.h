// Rows of one image level streamed in order, with rows and columns beyond its ends resolved by the domain.
#pragma once

#include <span>
#include <vector>

#include "gdp/topology.h"

namespace gdp::apps::tonemap {

// Column i (at most a few pixels outside [0, w)) of a row of width w: wrapped on the periodic
// domains (cylindrical, spherical), reflected about the edge (row -1 is row 0) on the plane.
int column(int i, int w, Domain domain);

// The last `keep` rows of a level of height h pushed in order y = 0, 1, ..., and rows just
// beyond either end: on the plane and the cylinder the reflected row (row -1 is row 0, row h
// is row h - 1: Neumann); on a spherical (PQ) domain the same rows read mirrored across the
// folds (row -1 - y is row y with column i read at W - 1 - i; row 2h - 1 - y is row y read at
// (W/2 - 1 - i) mod W), so filters see the image that continues across the folds.
class RowWindow {
 public:
  RowWindow(Domain domain, int width, int height, int keep);
  void push(std::span<const float> row);
  int pushed() const { return pushed_; }
  int width() const { return width_; }
  int height() const { return height_; }
  Domain domain() const { return domain_; }
  // Row y: one of the last `keep` pushed, or beyond an end and reflecting to one of them. The
  // span stays valid until the next push or until four more ghost rows have been asked for.
  std::span<const float> row(int y);

 private:
  std::span<const float> held(int y) const;

  Domain domain_;
  int width_, height_, keep_, pushed_ = 0;
  std::vector<std::vector<float>> ring_;
  std::vector<float> ghosts_[4];
  int next_ghost_ = 0;
};

}  // namespace gdp::apps::tonemap
