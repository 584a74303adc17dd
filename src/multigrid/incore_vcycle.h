// The in-core schedule: a V-cycle over whole planes held in memory (the reference schedule).
#pragma once

#include <functional>
#include <span>
#include <vector>

#include "multigrid/half_policy.h"
#include "multigrid/hierarchy.h"
#include "multigrid/plane.h"
#include "multigrid/row_kernels.h"  // row_dot, row_squares
#include "multigrid/window_ops.h"

namespace gdp::multigrid {

// Operator coefficients of every level in kernel precision, plus the coarsest in double.
template <class T>
struct Operators {
  const Hierarchy* hierarchy;
  std::vector<LevelOperator<T>> levels;
  LevelOperator<double> coarsest;
  bool singular;  // alpha == 0 (and no per-pixel weights): constants are in the null space

  explicit Operators(const Hierarchy& h);
  int count() const { return static_cast<int>(levels.size()); }
};

// What a V-cycle reports besides its result. With alpha == 0 a V-cycle does not fix the
// solution's constant; gdp fixes it by predicting the weighted sum <w, u> of the cycle's result
// as the sum over levels of <w_l, u_l> after pre-smoothing (coarsest: after the solve), where
// w_l = P^T w_{l-1} are the weights restricted to level l. Every schedule computes the same
// terms in the same order, so they choose the same constant.
struct CycleProbe {
  std::vector<double> dots;          // <w_l, u_l> per level (when weights are given)
  std::vector<double> level_norms;   // |r_l| after pre-smoothing, per level (coarsest: after the solve)
  bool sum_level_norms = true;       // fill level_norms (only log lines read them)
  // In-core only, asked for by the caller: |b - A u| on level `first` before and after the cycle,
  // summed in the cycle's own passes over the rows (the bits of InCoreVCycle::residual_norm).
  bool norm_before = false, norm_after = false;
  double before = 0.0, after = 0.0;
};

// Weights restricted to every level from `first` down (result[0] is level `first`). A weight plane of
// one row stands for a level whose rows are all that row (an image every pixel of which counts). With
// `held_once` the coarser levels hold each run of equal rows once (Plane::rows_of; the interior rows of a
// level restricted from equal rows are equal): only the rows made so far and those kept are mapped
// (docs/multigrid.md, "In-core memory on a PVM guest"). Read their rows with weight_row().
template <class T>
std::vector<Plane<T>> restrict_weights(const Operators<T>& ops, int first, Plane<T> w, bool held_once = false);
template <class T>
const T* weight_row(const Plane<T>& w, int j) {
  return w.row(!w.rows_of.empty() ? w.rows_of[j] : w.height == 1 ? 0 : j);
}

// Gathers the finest level's mean weights row by row (for restrict_weights): one row while every
// row is the same, the whole plane from the first row that differs (its pages are touched only
// then: fresh memory costs the most here, docs/multigrid.md, "In-core memory on a PVM guest").
template <class T>
class WeightRows {
 public:
  WeightRows(int width, int height) : height_(height), row_(width), plane_(width, height > 0 ? 1 : 0) {}
  std::span<T> next() { return row_; }  // where the next row goes; then add()
  void add();
  Plane<T> take() { return std::move(plane_); }

 private:
  int height_, rows_ = 0;
  std::vector<T> row_;
  Plane<T> plane_;
};

// The direction of a row's Gauss-Seidel sweep: always left to right (every schedule's), alternating
// from sweep to sweep, or alternating with row and sweep (a study's choices: bench/smoother_bench).
enum class SweepDirection { Forward, AlternateSweeps, AlternateRows };

// Two threads on one pass over a level's rows (InCoreVCycle::set_pair; the scheduler's, bands/incore_worker.h).
// A pass is `steps` steps; at each the lead does the first sweeps of its rows and the follower the rest
// (and the residual, restriction and sums) of the rows two a sweep above. The follower reads nothing the
// lead writes later and the lead nothing the follower writes, so the follower's step t only waits for the
// lead's: every relaxation sees what it sees on one thread, in the same order (same bits). (A fed b's
// ring is the exception: the lead reads rows into it, and waits for the follower before reusing a row.)
class PassPair {
 public:
  virtual ~PassPair() = default;
  // Runs lead() and follow() at once; returns when both have.
  virtual void run(int steps, const std::function<void()>& lead, const std::function<void()>& follow) = 0;
  // The lead has done steps [0, steps).
  virtual void ahead(int steps) = 0;
  // The follower waits until the lead has done step `step`.
  virtual void behind(int step) = 0;
  // The follower has done steps [0, steps) (said every kDoneEvery steps); the lead waits until it has
  // said so for `steps` (wait_done: once it must wait, until 2 kDoneEvery more, or the pass's last
  // word) before it reuses what the follower may still read.
  virtual void done(int steps) = 0;
  virtual void wait_done(int steps) = 0;
  static constexpr int kDoneEvery = 8;
};

// Level `first`'s b read in order, row by row, from where its owner keeps it (a row store), in place
// of a whole plane: InCoreVCycle::run keeps only the rows its passes are reading (a ring).
template <class T>
struct RowFeed {
  std::function<void()> rewind;                 // the next row read is row 0
  std::function<void(std::span<T> row)> read;   // the next row
  // Set by the V-cycle once it has rounded b to half floats (the half policy): rows are rounded as
  // they are read from then on (the bits of b rounded in place). One feed per right-hand side.
  bool rounded = false;
};

// Runs V-cycles on levels first, first + 1, ... Holds the storage of the levels below `first`:
// create one per thread and reuse it for many channels.
template <class T>
class InCoreVCycle {
 public:
  InCoreVCycle(const Operators<T>& ops, int sweeps, double coarse_tolerance, int first = 0);
  // One V-cycle for A u = b on level `first`, updating u. `weights` (restrict_weights(), may be
  // null) and `probe` (may be null) as described at CycleProbe. b is rounded in place where the
  // half policy says (the streamed V-cycle's stored b is what later cycles read).
  void run(Plane<T>& u, Plane<T>& b, const std::vector<Plane<T>>* weights = nullptr, CycleProbe* probe = nullptr);
  // The same with b fed row by row (the same bits).
  void run(Plane<T>& u, RowFeed<T>& b, const std::vector<Plane<T>>* weights = nullptr, CycleProbe* probe = nullptr);
  // |b - A u| on level `first`.
  double residual_norm(const Plane<T>& u, const Plane<T>& b);
  // A per-pixel diagonal term (window_ops.h) on every level: (*diag)[l - first] for level l
  // (restrict_weights() of the finest level's), or null for none. Not owned.
  void set_diagonal(const std::vector<Plane<T>>* diag);
  // Rounds each level's u and b to half floats after its restriction where `half` says
  // (half_policy.h), as the streamed V-cycle's stores do. Not owned; null: none.
  void set_half(const HalfPolicy* half);
  // `pre` sweeps before restriction and `post` after prolongation (the constructor's `sweeps` for
  // both; SolverOptions::sweeps and post_sweeps, as every schedule has them).
  void set_sweeps(int pre, int post);
  // Smoother studies (bench/smoother_bench): the counts and the rows' direction. Every schedule
  // has the default direction (left to right); others exist only in core.
  void set_smoother(int pre, int post, SweepDirection direction);
  // Levels of at least kPairRows rows are smoothed by two threads (PassPair); null: one. Not owned.
  void set_pair(PassPair* pair) { pair_ = pair; }
  static constexpr int kPairRows = 256;

 private:
  // A thread's temporaries: a residual row and the kernels' scratch.
  struct Lane {
    std::vector<T> r;
    Scratch<T> scratch;
  };
  // A level's b as the passes read it: a plane, or level `first`'s rows fed into `ring_`, rows
  // [0, fed) read so far, row j in ring row j % ring_.height.
  struct Rhs {
    Plane<T>* plane = nullptr;
    RowFeed<T>* feed = nullptr;
    int fed = 0;
  };
  const T* b_row(const Rhs& b, int j) const { return b.plane ? b.plane->row(j) : ring_.row(j % ring_.height); }
  void feed_to(Rhs& b, int j);
  static void rewind(Rhs& b) {
    if (b.feed) b.feed->rewind(), b.fed = 0;
  }
  void run(Plane<T>& u, Rhs b0, const std::vector<Plane<T>>* weights, CycleProbe* probe);
  template <class Lead, class Follow>
  void pass(int steps, int rows, const Lead& lead, const Follow& follow);
  double descend(int l, Plane<T>& u, Rhs& b, const Plane<T>* d, Plane<T>& coarse_b, const Plane<T>* w,
                 double& dots, bool norms, double* before);
  void ascend(int l, Plane<T>& u, Rhs& b, const Plane<T>* d, const Plane<T>& coarse, double* after);
  double row_residual2(int l, const Plane<T>& u, const T* b, const Plane<T>* d, int j, Lane& lane);
  Columns sweep_columns(const Columns& row, int sweep, int j) const;

  const Operators<T>& ops_;
  int sweeps_, post_sweeps_;
  SweepDirection direction_ = SweepDirection::Forward;
  double coarse_tolerance_;
  int first_;
  const std::vector<Plane<T>>* diag_ = nullptr;
  std::vector<char> half_u_, half_b_;  // per level from `first`: rounded after restriction
  Plane<double> coarse_diag_;           // the coarsest level's diagonal term in double ...
  std::vector<double> coarse_inverse_;  // ... and its CG preconditioner, computed once
  std::vector<Plane<T>> u_, b_;  // levels first + 1, ... (level `first` belongs to the caller)
  Plane<double> coarse_b_, coarse_u_;  // the coarsest level's b and u in double, reused
  Lane lane_, lead_;  // the follower's (and a single thread's) and the lead's
  Plane<T> ring_;    // fed rows of level `first`'s b (made at the first fed run)
  PassPair* pair_ = nullptr;
};

}  // namespace gdp::multigrid
