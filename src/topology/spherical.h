// Spherical topology: the periodic-quincuncial (PQ) rectangle, W = 4H, periodic left/right, with
// top and bottom edges that fold onto themselves.
#pragma once

#include "topology/topology.h"

namespace gdp::topology {

class Spherical final : public Topology {
 public:
  std::string_view name() const override { return "spherical"; }
  fem::AxisBoundary x_boundary() const override { return fem::AxisBoundary::Periodic; }
  fem::AxisBoundary y_boundary() const override { return fem::AxisBoundary::Mirrored; }
  std::pair<int, int> map(int i, int j, int w, int h) const override;
  // W = 4H with H even and at least 2.
  void validate_size(int w, int h) const override;
  // Both axes halve together, while H is even and at least 4 (every level is a PQ rectangle).
  std::pair<int, int> coarse_size(const fem::Axis& x, const fem::Axis& y) const override;
};

}  // namespace gdp::topology
