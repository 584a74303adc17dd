// Resampling targets: the direction of each output pixel and its extent on the sphere (internal).
#pragma once

#include <memory>
#include <span>
#include <vector>

#include "gdp/sphere.h"

namespace gdp::sphere {

// One output row: pixel centre directions d and the change of direction over one pixel along x
// (du) and along y (dv), from which the resampler gets footprints and sub-pixel positions.
struct TargetRow {
  std::vector<Vec3> d, du, dv;
};

// Produces rows of one output layout; one cursor per thread (it may cache neighbouring rows).
class TargetCursor {
 public:
  virtual ~TargetCursor() = default;
  virtual const TargetRow& row(int j) = 0;
};

std::unique_ptr<TargetCursor> make_target(const Projection& projection, int width, int height);

}  // namespace gdp::sphere
