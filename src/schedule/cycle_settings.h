// What a streamed V-cycle (streaming lanes and bands alike) is told about its problem and its scratch.
#pragma once

#include "gdp/solver.h"
#include "schedule/row_store.h"

namespace gdp::schedule {

struct CycleSettings {
  int channels = 1;
  int sweeps = 3;
  double coarse_tolerance = 1e-10;
  bool measure_initial = false;  // |b - A u| of the pushed rows (first cycle)
  bool measure_final = false;    // |b - A u| of the pulled rows
  bool weights = false;          // track <w_l, u_l> (multigrid::CycleProbe), for alpha == 0
  bool more_cycles = false;      // keep the finest weights for later cycles (b is always kept)
  bool diagonal = false;         // a per-pixel diagonal term (row_ops.h), pushed with b
  bool inputs_change = false;    // b, w and d are pushed again every cycle (a merged band stage's)
  StorePolicy stores;
};

// The settings a solve with `opt` gives its cycles: residuals measured, weights tracked for
// singular problems, scratch in the process's budget and then in opt.temp_dir (half floats with
// opt.half_scratch, or for opt.half_quantities).
inline CycleSettings cycle_settings(const SolverOptions& opt, bool singular, int channels, bool diagonal) {
  CycleSettings s;
  s.channels = channels;
  s.sweeps = opt.sweeps;
  s.coarse_tolerance = opt.coarse_tolerance;
  s.measure_initial = s.measure_final = true;
  s.weights = singular;
  s.diagonal = diagonal;
  s.more_cycles = opt.cycle_cap() > 1;
  s.stores.dir = opt.temp_dir;
  s.stores.budget = &ScratchBudget::process();
  s.stores.encoding = opt.half_scratch ? StoreEncoding::Half : StoreEncoding::Native;
  // The finest b is the problem's data, kept for later V-cycles: as half floats it moves their
  // answer by 2e-3 of the range (100x one V-cycle's error; docs/how-streaming-works.md).
  if (opt.half_scratch && s.more_cycles) s.stores.quantity_encoding["level0-b"] = StoreEncoding::Native;
  for (const std::string& q : opt.half_quantities) s.stores.quantity_encoding[q] = StoreEncoding::Half;
  return s;
}

}  // namespace gdp::schedule
