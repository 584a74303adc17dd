// The in-core schedule: a V-cycle over whole planes held in memory (the reference schedule).
#pragma once

#include <vector>

#include "multigrid/hierarchy.h"
#include "multigrid/plane.h"
#include "multigrid/row_ops.h"

namespace gdp::multigrid {

// Operator coefficients of every level in kernel precision, plus the coarsest in double.
template <class T>
struct Operators {
  const Hierarchy* hierarchy;
  std::vector<LevelOperator<T>> levels;
  LevelOperator<double> coarsest;
  bool singular;  // alpha == 0: constants are in the null space

  explicit Operators(const Hierarchy& h);
};

template <class T>
// Holds the coarse levels' storage: create one per thread and reuse it for many channels.
class InCoreVCycle {
 public:
  InCoreVCycle(const Operators<T>& ops, int sweeps, double coarse_tolerance);
  // One V-cycle for A u = b on the finest level, updating u. If level_residuals is given, it
  // receives |r| on each level after pre-smoothing (finest first).
  void run(Plane<T>& u, const Plane<T>& b, std::vector<double>* level_residuals = nullptr);
  // |b - A u| on the finest level.
  double residual_norm(const Plane<T>& u, const Plane<T>& b);

 private:
  const Operators<T>& ops_;
  int sweeps_;
  double coarse_tolerance_;
  std::vector<Plane<T>> u_, b_;  // levels 1.. (level 0 belongs to the caller)
  std::vector<T> tmp_, r_row_;
  RowScratch<T> scratch_;
};

}  // namespace gdp::multigrid
