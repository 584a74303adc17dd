// What a streamed V-cycle (streaming lanes and bands alike) is told about its problem and its scratch.
#pragma once

#include "gdp/solver.h"
#include "multigrid/half_policy.h"
#include "schedule/row_store.h"

namespace gdp::schedule {

struct CycleSettings {
  int channels = 1;  // the sweeps are the column plan's (bands::BandLayout::sweeps)
  double coarse_tolerance = 1e-10;
  bool weights = false;          // track <w_l, u_l> (multigrid::CycleProbe), for alpha == 0
  bool more_cycles = false;      // keep the finest weights for later cycles (b is always kept)
  bool diagonal = false;         // a per-pixel diagonal term (row_ops.h), pushed with b
  StorePolicy stores;
};

// The settings a solve with `opt` gives its cycles: residuals measured, weights tracked for
// singular problems, scratch in the process's budget and then in opt.temp_dir (half floats with
// multigrid::half_policy(opt), which the in-core V-cycle applies alike).
inline CycleSettings cycle_settings(const SolverOptions& opt, bool singular, int channels, bool diagonal) {
  CycleSettings s;
  s.channels = channels;
  s.coarse_tolerance = opt.coarse_tolerance;
  s.weights = singular;
  s.diagonal = diagonal;
  s.more_cycles = opt.cycle_cap() > 1;
  s.stores.dir = opt.temp_dir;
  s.stores.budget = &ScratchBudget::process();
  s.stores.half = multigrid::half_policy(opt);
  return s;
}

}  // namespace gdp::schedule
