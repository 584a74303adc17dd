// RankShare: the one place gdp sky's passes set up their MPI hub and PlateShare.
#include "sky/rank_share.h"

#include "bands/mpi_transport.h"
#include "gdp/mpi_run.h"

namespace gdp::sky {

RankShare::RankShare(const std::function<std::vector<int>(int ranks)>& owners) {
  const int ranks = MpiRun::size();
  if (ranks <= 1) return;
  hub_ = std::make_unique<bands::MpiHub>(1);
  share_.net = &hub_->own();
  if (owners) share_.owners = owners(ranks);
  share_.agree = MpiRun::agree;
}

RankShare::~RankShare() = default;

}  // namespace gdp::sky
