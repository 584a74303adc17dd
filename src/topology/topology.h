// The small interface every domain topology implements: boundaries per axis and index map.
#pragma once

#include <memory>
#include <string_view>
#include <utility>

#include "fem/axis.h"
#include "gdp/topology.h"

namespace gdp::topology {

class Topology {
 public:
  virtual ~Topology() = default;
  virtual std::string_view name() const = 0;
  virtual fem::AxisBoundary x_boundary() const = 0;
  virtual fem::AxisBoundary y_boundary() const = 0;
  // Where a stencil reaching sample (i, j) outside [0,w) x [0,h) actually reads; the
  // identity inside. Planar reflects, cylindrical wraps i and reflects j.
  virtual std::pair<int, int> map(int i, int j, int w, int h) const = 0;
  // Throws UsageError when an image of this size cannot live on this domain.
  virtual void validate_size(int w, int h) const = 0;
  // The size of the next coarser multigrid level; (x.n, y.n) when the hierarchy stops here.
  // By default each axis halves on its own while it can.
  virtual std::pair<int, int> coarse_size(const fem::Axis& x, const fem::Axis& y) const {
    return {fem::next_size(x), fem::next_size(y)};
  }
};

std::unique_ptr<Topology> make_topology(Domain d);

}  // namespace gdp::topology
