// The plate passes' PlateShare of this process: under mpirun, the ranks joined through an MPI hub.
#pragma once

#include <functional>
#include <memory>
#include <vector>

#include "sky/plate_exchange.h"

namespace gdp::bands {
class MpiHub;
}

namespace gdp::sky {

// Under mpirun (more than one rank; constructing is then collective): a hub of one lane the
// exchanges go through, errors agreed with gdp::MpiRun::agree, and plate k run by rank
// owners(ranks)[k] where `owners` is given (else every plate rank 0's). One process: PlateShare's
// default. The share is valid while this lives.
class RankShare {
 public:
  explicit RankShare(const std::function<std::vector<int>(int ranks)>& owners = {});
  ~RankShare();
  RankShare(const RankShare&) = delete;
  RankShare& operator=(const RankShare&) = delete;
  const PlateShare& share() const { return share_; }

 private:
  std::unique_ptr<bands::MpiHub> hub_;
  PlateShare share_;
};

}  // namespace gdp::sky
