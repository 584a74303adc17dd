// The input ring: decoded rows and each unit's input rows, made by whichever worker needs them first.
#include "schedule/input_ring.h"

#include <algorithm>

#include "util/env_int.h"

namespace gdp::schedule {

template <class T>
InputRing<T>::InputRing(GuidanceSource& source, const multigrid::Hierarchy& hierarchy, const std::vector<Unit>& units,
                        Marks& marks, std::function<void(double)> progress)
    : slots_(std::max(kUnitSlots, util::env_int("GDP_INPUT_ROWS", 16))),
      source_(source), marks_(marks), finished_(marks.add(static_cast<int>(units.size()))) {
  if (source.splits()) {
    const int decoded = std::max(kDecodedSlots, slots_);
    source.set_slots(decoded);
    decoded_ = std::make_unique<RowRing>(marks, static_cast<int>(units.size()), decoded, source.height(),
                                         [&source](int y) { source.decode(y); });
  }
  for (std::size_t l = 0; l < units.size(); ++l)
    units_.push_back(std::make_unique<Made>(*this, units[l], static_cast<int>(l), hierarchy, l == 0 ? progress : nullptr));
}

template <class T>
InputRing<T>::Made::Made(InputRing& in, const Unit& unit, int l, const multigrid::Hierarchy& hierarchy,
                         std::function<void(double)> progress)
    : input(in.source_, hierarchy, unit.sums, unit.rows,
            [&in, l, g = unit.guidance](int j, GuidanceRow& row) {
              if (!in.decoded_) return in.source_.read_row(j, row);
              in.decoded_->need(l, j, std::min(j + 1, in.source_.height() - 1));  // the right-hand side reads row j + 1
              in.source_.compute(j, row, g.first, g.second);
            }),
      u(static_cast<std::size_t>(in.slots_) * in.source_.channels() * in.source_.width()), b(u.size()),
      w(static_cast<std::size_t>(in.slots_) * in.source_.width()), d(in.source_.has_weights() ? w.size() : 0),
      ring(in.marks_, unit.readers, in.slots_, in.source_.height(), [this, &in, l, progress](int j) {
        input.next(in.slot(u, j), in.slot(b, j), in.slot(w, j), in.slot(d, j));
        const int h = in.source_.height();
        if (progress && (j % 64 == 63)) progress(0.5 * (j + 1) / h);
        if (j + 1 == h) in.marks_.set(in.finished_ + l, 1);
      }) {}

template <class T>
typename InputRing<T>::Row InputRing<T>::row(int l, int r, int j) {
  Made& m = *units_[l];
  m.ring.need(r, j, j);
  return {slot(m.u, j), slot(m.b, j), slot(m.w, j), slot(m.d, j)};
}

template <class T>
std::vector<multigrid::InputTotals> InputRing<T>::totals() {
  marks_.wait(finished_, finished_ + static_cast<int>(units_.size()), 0, 0);
  std::vector<multigrid::InputTotals> all;
  for (const auto& m : units_) all.insert(all.end(), m->input.range_totals().begin(), m->input.range_totals().end());
  return all;
}

template <class T>
double InputRing<T>::column_cpu() const {
  double cpu = -decode_cpu();
  for (const auto& m : units_) cpu += m->ring.cpu;
  return cpu;
}

template class InputRing<float>;
template class InputRing<double>;

}  // namespace gdp::schedule
