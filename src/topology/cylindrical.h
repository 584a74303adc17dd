// Cylindrical topology: periodic left/right edges (360-degree panoramas), Neumann top/bottom.
#pragma once

#include "topology/topology.h"

namespace gdp::topology {

class Cylindrical final : public Topology {
 public:
  std::string_view name() const override { return "cylindrical"; }
  fem::AxisBoundary x_boundary() const override { return fem::AxisBoundary::Periodic; }
  fem::AxisBoundary y_boundary() const override { return fem::AxisBoundary::Neumann; }
  std::pair<int, int> map(int i, int j, int w, int h) const override;
  void validate_size(int w, int h) const override;
};

}  // namespace gdp::topology
