// Where a streamed solve's scratch goes under the --memory budget: bounds on the memory and disk it takes.
#pragma once

#include <algorithm>
#include <limits>

namespace gdp::cli {

struct ScratchSplit {
  double memory = 0.0;  // at most this much of the scratch is in memory
  double disk = 0.0;    // at most this much is in files
};

// `scratch` bytes of row stores, none larger than `largest_store`, under a `budget`: a store stays
// in memory only if it fits whole in what the budget has left, else it goes to a file whole
// (schedule::ScratchBudget). So when not everything fits, a store was refused while more than
// budget - that store was held: at least budget - largest_store stays in memory, and the disk
// takes the rest, up to a store more than scratch - budget. Stores of `direct_from` bytes or more
// are files whatever the budget (O_DIRECT, GDP_DIRECT_SCRATCH): with such a store all of it may be.
inline ScratchSplit split_scratch(double scratch, double budget, double largest_store,
                                  double direct_from = std::numeric_limits<double>::infinity()) {
  const double disk = largest_store >= direct_from ? scratch : 0.0;
  if (scratch <= budget) return {scratch, disk};
  return {budget, std::max(disk, scratch - std::max(0.0, budget - largest_store))};
}

}  // namespace gdp::cli
