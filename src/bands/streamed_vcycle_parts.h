// What the band V-cycle's source files share: a level's storage, message tags, byte packing.
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "bands/band_fold.h"
#include "bands/streamed_vcycle.h"

namespace gdp::bands {

// Message tags: level l's strips use tag l, its rows across the fold kFoldRows + l and its
// restriction's sums across the fold kFoldSums + l; the collectives use the others.
constexpr int kGather = 1000, kSums = 1001, kFinal = 1002, kFoldRows = 1100, kFoldSums = 1200, kHandOff = 1300,
              kHandBack = 1301, kSaved = 1400;
// Every stage's tags (and solve_streamed' 2000) are below this; a merged stage's are moved past it.
constexpr int kStageTags = 4000;

// The merged stage's workers over `outer`'s (streamed_exchange.cc): merged band g is worker 2g.
std::unique_ptr<Transport> merged_transport(Transport& outer, int bands);

// Side 0: the top fold (rows 0, 1), side 1: the bottom one (rows h - 2, h - 1).
constexpr fem::Mirror kSides[2] = {fem::Mirror::Top, fem::Mirror::Bottom};
inline int side_of(fem::Mirror m) { return m == fem::Mirror::Top ? 0 : 1; }

template <class T>
struct StreamedVCycle<T>::Level {
  const multigrid::LevelOperator<T>* op = nullptr;
  int width = 0, height = 0, ring = 0;
  int A = 0, B = 0, origin = 0, len = 0;  // owned columns [A, B); row storage from column origin
  std::vector<T> u, b, w, d;              // ring slots: channels * len (w, d: len)
  multigrid::Scratch<T> scratch;
  int phases = 0;         // phases per pass (band_phase.h)
  int arrived = 0;        // rows that entered this pass
  int next_phase = 0;     // the next phase to run
  int finished = 0;       // rows restricted (or measured) in this pass
  int zeroed = 0;         // restriction pass: coarser rows cleared for accumulation
  int next_complete = 0;  // restriction pass: coarser rows completed by this level
  int needed_from = 0;    // prolongation pass: lowest row the finer level still reads
  std::vector<int> last_touch;
  std::unique_ptr<schedule::RowStore<T>> u_store, b_store, w_store, d_store;
  std::array<schedule::RowStore<T>*, 4> stores() const { return {u_store.get(), b_store.get(), w_store.get(), d_store.get()}; }
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

}  // namespace gdp::bands
