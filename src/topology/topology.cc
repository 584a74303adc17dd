// Topology factory and domain names.
#include "topology/topology.h"

#include <fmt/format.h>

#include "gdp/errors.h"
#include "topology/cylindrical.h"
#include "topology/planar.h"
#include "topology/spherical.h"

namespace gdp {

Domain parse_domain(std::string_view name) {
  if (name == "planar") return Domain::Planar;
  if (name == "cylindrical") return Domain::Cylindrical;
  if (name == "spherical" || name == "pq") return Domain::Spherical;
  throw UsageError(fmt::format("unknown domain '{}' (expected planar, cylindrical or spherical)", name));
}

namespace topology {

std::unique_ptr<Topology> make_topology(Domain d) {
  switch (d) {
    case Domain::Cylindrical: return std::make_unique<Cylindrical>();
    case Domain::Spherical: return std::make_unique<Spherical>();
    case Domain::Planar: break;
  }
  return std::make_unique<Planar>();
}

}  // namespace topology
}  // namespace gdp
