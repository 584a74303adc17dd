// The input pass by band: guidance rows decoded once, each unit's input rows made from them, on demand.
#pragma once

#include <functional>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "gdp/guidance.h"
#include "multigrid/hierarchy.h"
#include "multigrid/input_rows.h"
#include "schedule/parallel.h"

namespace gdp::schedule {

// A unit is a set of bands whose input rows one InputRows makes (one per band where the source
// splits, GuidanceSource::splits; else one for all, reading whole rows). Its readers (the workers
// of its bands) make its rows as they need them into a RowRing of 16 slots, and a unit making a
// row decodes the source's rows it needs into one of 16 shared by the units: no thread of its own
// decodes or makes rows. No slot wait hangs, however far readers drift, with kUnitSlots and
// kDecodedSlots or more (docs/how-bands-work.md, "Why a streamed solve cannot hang"; GDP_INPUT_ROWS).
template <class T>
class InputRing {
 public:
  using Range = std::pair<int, int>;  // columns [first, second)
  struct Unit {
    std::vector<Range> sums;  // its bands' own columns, whose sums are kept apart
    Range rows, guidance;     // the columns it makes, and those of the guidance they read
    int readers;
  };
  InputRing(GuidanceSource& source, const multigrid::Hierarchy& hierarchy, const std::vector<Unit>& units, Marks& marks,
            std::function<void(double)> progress = {});
  // Whole rows, the unit's columns made (the others 0): u and b channels x width, w and d width
  // (d empty without per-pixel weights).
  struct Row {
    std::span<const T> u, b, w, d;
  };
  // Reader r of unit l: row j (rows in order).
  Row row(int l, int r, int j);
  // Reader r of unit l reads no more; returns once the unit has made every row (its sums are final).
  void done(int l, int r) { units_[l]->ring.done(r); }
  // Waits until every unit has made every row, then: each unit's sums over its ranges, in order.
  std::vector<multigrid::InputTotals> totals();
  double decode_cpu() const { return decoded_ ? decoded_->cpu : 0.0; }
  double column_cpu() const;

 private:
  // From RowRing's slack and look-ahead; a unit's row j reads decoded rows up to j + 2.
  static constexpr int kUnitSlots = RowRing::kSlack + 1, kDecodedSlots = RowRing::kAhead + RowRing::kSlack + 3;
  const int slots_;  // per unit (16; GDP_INPUT_ROWS, never below kUnitSlots)
  // Row j's slot in a ring of slots_ rows (empty where the ring is).
  std::span<T> slot(std::vector<T>& ring, int j) const {
    const std::size_t n = ring.size() / slots_;
    return {ring.data() + j % slots_ * n, n};
  }
  struct Made {
    Made(InputRing& in, const Unit& unit, int l, const multigrid::Hierarchy& hierarchy, std::function<void(double)> progress);
    multigrid::InputRows<T> input;
    std::vector<T> u, b, w, d;  // slots_ rows each
    RowRing ring;
  };
  GuidanceSource& source_;
  Marks& marks_;
  int finished_;  // marks: unit l has made every row (finished_ + l)
  std::unique_ptr<RowRing> decoded_;  // when the source splits
  std::vector<std::unique_ptr<Made>> units_;
};

}  // namespace gdp::schedule
