// Planar topology: Neumann boundaries on all four sides.
#pragma once

#include "topology/topology.h"

namespace gdp::topology {

class Planar final : public Topology {
 public:
  std::string_view name() const override { return "planar"; }
  fem::AxisBoundary x_boundary() const override { return fem::AxisBoundary::Neumann; }
  fem::AxisBoundary y_boundary() const override { return fem::AxisBoundary::Neumann; }
  std::pair<int, int> map(int i, int j, int w, int h) const override;
  void validate_size(int w, int h) const override;
};

}  // namespace gdp::topology
