// The streamed V-cycle: the one-band plan is plain streaming, N bands the paper's section 6.
#pragma once

#include <array>
#include <cmath>
#include <memory>
#include <span>
#include <vector>

#include "bands/band_fold.h"
#include "bands/band_layout.h"
#include "bands/transport.h"
#include "multigrid/window_ops.h"
#include "gdp/solver.h"
#include "multigrid/half_policy.h"
#include "multigrid/incore_vcycle.h"
#include "schedule/row_store.h"
#include "schedule/bytes.h"

namespace gdp::bands {

// Message tags: level l's strips use tag l, its rows across the fold kFoldRows + l and its
// restriction's sums across the fold kFoldSums + l; the collectives use the others (the solve's
// own: the input's sums and the checkpoint's agreement).
constexpr int kGather = 1000, kSums = 1001, kFinal = 1002, kFoldRows = 1100, kFoldSums = 1200, kHandOff = 1300,
              kHandBack = 1301, kSaved = 1400, kTotals = 2000, kGenerations = 2001;
// Every stage's tags are below this; a merged stage's are moved past it.
constexpr int kStageTags = 4000;

// What a streamed V-cycle is told about its problem and its scratch (sweeps: the column plan's).
struct CycleSettings {
  int channels = 1;              // the worker's (CycleWorker sets them)
  double coarse_tolerance = 1e-10;
  bool weights = false;          // track <w_l, u_l> (multigrid::CycleProbe), for alpha == 0
  bool more_cycles = false;      // keep the finest weights for later cycles (b is always kept)
  bool diagonal = false;         // a per-pixel diagonal term (row_ops.h), pushed with b
  bool level_norms = true;       // sum every level's |r|^2 (the probe's level_norms: only log lines read them)
  bool residuals = true;         // level 0's |b - A u| before and after the cycle (initial_norm, final_norm)
  schedule::StorePolicy stores;
};

// The settings a solve with `opt` gives its cycles: weights tracked for singular problems, scratch
// in the process's budget, then in opt.temp_dir, half floats as the in-core V-cycle rounds them.
inline CycleSettings cycle_settings(const SolverOptions& opt, bool singular, bool diagonal) {
  CycleSettings s{.coarse_tolerance = opt.coarse_tolerance, .weights = singular, .more_cycles = opt.cycle_cap() > 1,
                  .diagonal = diagonal, .level_norms = static_cast<bool>(opt.log), .residuals = opt.measures_residuals(),
                  .stores = {}};
  s.stores.dir = opt.temp_dir;
  s.stores.half = multigrid::half_policy(opt, diagonal);
  return s;
}

// One V-cycle as the paper's two passes over the rows, all levels in lockstep, on band
// `transport.rank()` of the column plan `layout` (docs/how-streaming-works.md, docs/how-bands-work.md):
// rows are pushed in order and relaxed in groups (group t: sweep s of row t - 2s), G groups a phase
// (band_phase.h); a row whose neighbours are final is restricted and the coarse rows it completes
// enter the next level; the first level held whole is gathered to worker 0 and solved in-core (or
// handed to the merged stage); rows are then pulled in order, each read back from the stores, given
// the prolonged correction and post-smoothed alike. The one-band plan (BandLayout::single) is
// plain streaming and gives in-core's bits. Rows handed in and out are a band's columns with
// `layout.halo` columns of each neighbour: channels * layout.row_length(0, band) samples (w: one).
template <class T>
class StreamedVCycle {
 public:
  StreamedVCycle(const multigrid::Operators<T>& ops, const BandLayout& layout, Transport& transport,
             const CycleSettings& settings);

  void begin_cycle();
  // Restriction pass: the next finest row's ring slots to fill, then push(): u, and b, w and d where
  // it takes them (the first cycle's; later from the stores: empty).
  struct Slots { std::span<T> u, b, w, d; };
  Slots next_row();
  void push();
  // Prolongation pass: the next finished row, halo columns included.
  void pull(std::span<T> u);

  // After the cycle, the same on every worker: sums over all bands (the norms 0 unless the
  // settings' residuals).
  const multigrid::CycleProbe& probe(int c) const { return probes_[c]; }
  double initial_norm(int c) const { return std::sqrt(initial_rr_[c]); }
  double final_norm(int c) const { return std::sqrt(final_rr_[c]); }
  // Bytes held (a merged stage's included): in its rings and buffers, and in its row stores so far.
  struct Held { std::size_t window = 0, scratch = 0; };
  Held bytes();
  const BandLayout& layout() const { return layout_; }

  // Checkpoints (stores kept in files: StorePolicy::keep_dir), between two pushes or between
  // passes: saving makes the row stores durable and writes what the worker holds (held(): a merged
  // stage's too); loading puts it back and truncates the stores to their saved lengths.
  // CorruptState when the blob does not fit this cycle's shape. Every band of a plan saves at the
  // same row (docs/resume.md). (save: a ByteWriter, load: a ByteReader).
  template <class Archive>
  void state(Archive& archive);
  // After every band's save: returns once all bands of the plan have saved (so that no band is
  // ever two saves ahead of another, docs/resume.md). Nothing to wait for with one band.
  void saved() { all_gather(net_, kSaved, {}); }

 private:
  enum Quantity { U, B, W, D };  // a level's u, b (every channel), w and d (one row)
  int per(int q) const { return q < W ? set_.channels : 1; }
  bool has(int q) const { return q < W || (q == W ? set_.weights : set_.diagonal); }
  struct Level {
    const multigrid::LevelOperator<T>* op = nullptr;
    int width = 0, height = 0, ring = 0;
    int A = 0, B = 0, origin = 0, len = 0;  // owned columns [A, B); row storage from column origin
    std::array<std::vector<T>, 4> ring_of;  // per quantity (U, B, W, D): ring slots of per(q) * len
    multigrid::Scratch<T> scratch;
    int arrived = 0;        // rows that entered this pass
    int next_phase = 0;     // the next phase to run
    int finished = 0;       // rows restricted (or measured) in this pass
    int zeroed = 0;         // restriction pass: coarser rows cleared for accumulation
    int next_complete = 0;  // restriction pass: coarser rows completed by this level
    int needed_from = 0;    // prolongation pass: lowest row the finer level still reads
    std::vector<int> last_touch;
    std::array<std::unique_ptr<schedule::RowStore<T>>, 4> store;  // per quantity, where kept
    bool inputs_stored = false;
    std::vector<double> rr, dots;
    // Spherical levels (layout.folded), per side: who sees which columns across the fold, and the
    // two rows there as the last exchange showed them (channels x 2 rows x width, whole rows).
    struct Fold {
      FoldPlan reads, sums;  // sums: this level's restriction into the next one
      std::vector<T> rows;
    };
    std::array<Fold, 2> fold;
  };
  // Everything this stage holds, in the order a checkpoint saves it: f gets every buffer
  // (std::span<T>), counter and flag, vector of sums and row store (RowStore<T>*, maybe null).
  template <class F>
  void held(F&& f);
  std::unique_ptr<Level> make_level(int l);
  void advance(int l);
  void strip(int l, int p, bool left, bool outgoing);
  // |b - A u|^2 of level 0's row j (`initial`: as pushed in the first cycle) added to rr per channel.
  void measure(int j, bool initial, std::vector<double>& rr);
  void restrict_row(int l, int j);
  void run_tail();
  void hand(int row, bool off);  // to the merged stage (restriction pass) or back
  void ensure_final(int l, int row);
  void check_slot(int l, int row) const;
  // Row j's window on level l, channel c; `initial`: level 0's rows as pushed in the first cycle.
  multigrid::Window<T> window(int l, int c, int j, bool initial = false);
  // Columns [begin, end) of a level n wide.
  multigrid::Columns columns(int n, int begin, int end, bool forward = true) const;
  // Spherical levels (docs/how-bands-work.md, "Across the fold"): row `row` (0, 1, h-2 or h-1),
  // whole, as the last exchange across the fold showed it.
  T* fold_row(int l, int c, int row, bool initial = false);
  void exchange_fold_rows(int l, int side, std::vector<T>& into);
  void add_fold_sums(int l, int side, const std::vector<T>& sums, int row);
  // Channel c's part of quantity q's slot for row j on level l (null: no such ring), and the slot.
  T* ring_row(int l, int q, int j, int c = 0) {
    Level& L = *levels_[l];
    return L.ring_of[q].empty() ? nullptr : L.ring_of[q].data() + (static_cast<std::size_t>(j % L.ring) * per(q) + c) * L.len;
  }
  std::span<T> slot_of(int l, int q, int j) { return {ring_row(l, q, j), static_cast<std::size_t>(per(q)) * levels_[l]->len}; }
  // The inputs of level l's row j as parts: b of channel k < channels, then w and d where the
  // settings have them.
  int parts() const { return set_.channels + (set_.weights ? 1 : 0) + (set_.diagonal ? 1 : 0); }
  T* part_row(int l, int k, int j) { return k < set_.channels ? ring_row(l, B, j, k) : ring_row(l, has(W) && k == set_.channels ? W : D, j); }

  const multigrid::Operators<T>& ops_;
  const BandLayout& layout_;      // the restriction pass's plan
  const BandLayout post_layout_;  // the prolongation pass's (BandLayout::post_pass)
  // The plan of the pass under way.
  const BandLayout& plan() const { return prolongation_ ? post_layout_ : layout_; }
  Transport& net_;
  CycleSettings set_;
  int band_;
  int base_;  // the hierarchy level of this stage's level 0
  std::vector<std::unique_ptr<Level>> levels_;
  multigrid::Plane<T> tail_u_, tail_b_;  // worker 0: a channel of the gathered level as the tail solves it
  std::vector<multigrid::Plane<T>> tail_diag_;  // worker 0: tail_d_ restricted to the tail's levels
  std::unique_ptr<multigrid::InCoreVCycle<T>> tail_;
  // A merged stage below this one (layout.merged; on the worker owning this band's group).
  std::unique_ptr<Transport> merged_net_;
  std::unique_ptr<StreamedVCycle<T>> merged_;
  std::vector<T> initial_;  // first cycle of the top stage: a ring of level-0 rows as pushed
  std::array<std::vector<T>, 2> initial_fold_;  // first cycle: level 0's rows across the fold as pushed
  std::vector<multigrid::CycleProbe> probes_;
  std::vector<double> initial_rr_, final_rr_;
  std::vector<T> r_;
  int cycle_ = 0, pulled_ = 0;
  bool prolongation_ = false;
};

}  // namespace gdp::bands
