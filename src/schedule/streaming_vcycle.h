// The streaming schedule of one V-cycle: two passes over the rows, all levels in lockstep.
#pragma once

#include <cmath>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "multigrid/incore_vcycle.h"
#include "schedule/cycle_settings.h"
#include "schedule/row_store.h"
#include "schedule/state_io.h"

namespace gdp::schedule {

// One V-cycle as the paper's two passes (docs/how-streaming-works.md):
//  - restriction pass: rows of the finest level are pushed in order; on every level each new
//    row lets sweep s relax the row 2s above it, the residual of the row below the last sweep
//    is restricted into the coarser level, and a coarse row whose last contribution arrived
//    is pushed there in turn. Pre-smoothed u and b go to row stores.
//  - the levels from `incore_from` down are small and are held whole: when the restriction
//    pass has filled them, they run an in-core V-cycle.
//  - prolongation pass: rows are pulled in order; a row is read back, gets the prolonged
//    correction of the coarser level (pulled on demand) and is post-smoothed by the same
//    pipeline of sweeps.
// Each level keeps a ring of a few rows. The arithmetic per row is exactly the in-core
// schedule's, so the results are bit-identical.
template <class T>
class StreamingVCycle {
 public:
  struct Settings : CycleSettings {
    int incore_from = 1;  // first level held whole (1 .. levels - 1)
  };

  StreamingVCycle(const multigrid::Operators<T>& ops, const Settings& settings);
  ~StreamingVCycle();

  // Starts a V-cycle (the first, or another one on the rows pulled from the previous).
  void begin_cycle();
  // Restriction pass: the next finest row; u and b hold channels * width samples, w and d width
  // samples. b, w and d are stored during the first cycle: later cycles pass empty spans.
  void push(std::span<const T> u, std::span<const T> b, std::span<const T> w, std::span<const T> d = {});
  // Prolongation pass (after the last push): the next finished row, channels * width samples.
  void pull(std::span<T> u);

  // Per channel, after the cycle: weighted sums and per-level residual norms (as in-core).
  const multigrid::CycleProbe& probe(int c) const { return probes_[c]; }
  double initial_norm(int c) const { return std::sqrt(initial_rr_[c]); }
  double final_norm(int c) const { return std::sqrt(final_rr_[c]); }
  // Bytes written to row stores in this cycle (on disk or in memory) and held in memory now.
  std::size_t store_bytes() const;
  std::size_t window_bytes() const;

  // Checkpoints (stores kept in files: StorePolicy::keep_dir), between two pushes or between
  // passes: save() makes the row stores durable and writes the whole state (rings, counters,
  // the in-core tail, probes, the stores' lengths); load() puts it back and truncates the
  // stores to those lengths. CorruptState when the blob does not fit this cycle's shape.
  void save(StateWriter& out);
  void load(StateReader& in);

 private:
  struct Level;
  enum class Stage { MeasureInitial, Sweep, Restrict, MeasureFinal };

  void arrive(int l);
  void advance(int l);
  void run_stage(int l, Stage stage, int j);
  void restrict_into_coarser(int l, int j);
  void complete_coarse_row(int l);
  void run_incore();
  void ensure_final(int l, int row);
  void check_slot(int l, int row) const;
  multigrid::Window<T> window(int l, int c, int j);  // rows j-2 .. j+2 of channel c
  T* u_row(int l, int c, int j);
  T* b_row(int l, int c, int j);
  T* w_row(int l, int j);
  T* d_row(int l, int j);  // null without a diagonal term

  const multigrid::Operators<T>& ops_;
  Settings set_;
  std::vector<std::unique_ptr<Level>> levels_;  // the streamed levels 0 .. incore_from - 1
  // The in-core tail: level incore_from per channel, its weights, and the V-cycle below it.
  std::vector<multigrid::Plane<T>> tail_u_, tail_b_;
  multigrid::Plane<T> tail_w_, tail_d_;
  std::vector<multigrid::Plane<T>> tail_diag_;  // tail_d_ restricted to the tail's levels
  std::unique_ptr<multigrid::InCoreVCycle<T>> tail_;
  std::vector<multigrid::CycleProbe> probes_;
  std::vector<double> initial_rr_, final_rr_;
  std::vector<T> r_;
  int cycle_ = 0;
  bool prolongation_ = false;
};

}  // namespace gdp::schedule
