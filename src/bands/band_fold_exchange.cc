// Band V-cycle across a spherical level's fold: rows shown to mirror partners, restriction sums sent to owners.
#include <algorithm>

#include "bands/streamed_vcycle_parts.h"

namespace gdp::bands {

template <class T>
T* StreamedVCycle<T>::fold_row(int l, int c, int row, bool initial) {
  Level& L = *levels_[l];
  const int side = row < 2 ? 0 : 1, r = side == 0 ? row : row - (L.height - 2);
  T* rows = initial ? initial_fold_[side].data() : L.fold[side].rows.data();
  return rows + (static_cast<std::size_t>(c) * 2 + r) * L.width;
}

// Rows 0, 1 (side 0) or h - 2, h - 1 (side 1) of level l as they are now, at the columns across
// the fold this band reads, into `into` (whole rows): its own copied, the others' from their owners.
template <class T>
void StreamedVCycle<T>::exchange_fold_rows(int l, int side, std::vector<T>& into) {
  Level& L = *levels_[l];
  const FoldPlan& plan = L.fold[side].reads;
  const int first = side == 0 ? 0 : L.height - 2;
  const auto pieces = [&](const ColumnRuns& runs, auto&& f) {
    for (int c = 0; c < set_.channels; ++c)
      for (int r = 0; r < 2; ++r)
        for (auto [x0, x1] : runs) f(c, r, x0, static_cast<std::size_t>(x1 - x0));
  };
  const auto own = [&](int c, int r, int x) { return u_row(l, c, first + r) + (x - L.origin); };
  const auto at = [&](int c, int r, int x) { return into.data() + (static_cast<std::size_t>(c) * 2 + r) * L.width + x; };
  for (int b = 0; b < layout_.bands; ++b) {
    if (b == band_ || !plan.sends(b)) continue;
    Packer pk;
    pieces(plan.to[b], [&](int c, int r, int x, std::size_t n) { pk.put(own(c, r, x), n); });
    net_.send(b, kFoldRows + l, std::move(pk.bytes));
  }
  pieces(plan.from[band_], [&](int c, int r, int x, std::size_t n) { std::copy_n(own(c, r, x), n, at(c, r, x)); });
  for (int b = 0; b < layout_.bands; ++b) {
    if (b == band_ || !plan.receives(b)) continue;
    const Bytes bytes = net_.receive(b, kFoldRows + l);
    Unpacker un(bytes);
    pieces(plan.from[b], [&](int c, int r, int x, std::size_t n) { un.get(at(c, r, x), n); });
    un.finish();
  }
}

// Level l's restriction across the fold into coarse row `row`: `sums` holds this band's
// contributions at the mirror image of its coarse columns (whole rows: b per channel, then w and d
// as the settings have them); each goes to the band owning the column, which adds them (its own
// first, then the others' in band order).
template <class T>
void StreamedVCycle<T>::add_fold_sums(int l, int side, const std::vector<T>& sums, int row) {
  const FoldPlan& plan = levels_[l]->fold[side].sums;
  const bool tail = gathered(l);
  const int m = ops_.levels[base_ + l + 1].width, channels = set_.channels;
  const int parts = channels + (set_.weights ? 1 : 0) + (set_.diagonal ? 1 : 0);
  const int corigin = tail ? 0 : levels_[l + 1]->origin;
  const auto coarse = [&](int k) -> T* {  // part k of coarse row `row`, at column corigin
    if (k < channels) return tail ? tail_b_[k].row(row) : b_row(l + 1, k, row);
    if (k == channels && set_.weights) return tail ? tail_w_.row(row) : w_row(l + 1, row);
    return tail ? tail_d_.row(row) : d_row(l + 1, row);
  };
  const auto pieces = [&](const ColumnRuns& runs, auto&& f) {
    for (int k = 0; k < parts; ++k)
      for (auto [x0, x1] : runs) f(k, x0, static_cast<std::size_t>(x1 - x0));
  };
  const auto add = [&](int k, int x, const T* v, std::size_t n) {
    T* to = coarse(k) + (x - corigin);
    for (std::size_t i = 0; i < n; ++i) to[i] += v[i];
  };
  for (int b = 0; b < layout_.bands; ++b) {
    if (b == band_ || !plan.sends(b)) continue;
    Packer pk;
    pieces(plan.to[b], [&](int k, int x, std::size_t n) { pk.put(sums.data() + static_cast<std::size_t>(k) * m + x, n); });
    net_.send(b, kFoldSums + l, std::move(pk.bytes));
  }
  pieces(plan.from[band_],
         [&](int k, int x, std::size_t n) { add(k, x, sums.data() + static_cast<std::size_t>(k) * m + x, n); });
  std::vector<T> got;
  for (int b = 0; b < layout_.bands; ++b) {
    if (b == band_ || !plan.receives(b)) continue;
    const Bytes bytes = net_.receive(b, kFoldSums + l);
    Unpacker un(bytes);
    pieces(plan.from[b], [&](int k, int x, std::size_t n) {
      got.resize(n);
      un.get(got.data(), n);
      add(k, x, got.data(), n);
    });
    un.finish();
  }
}

#define GDP_INSTANTIATE(T)                                                                        \
  template T* StreamedVCycle<T>::fold_row(int, int, int, bool);                                     \
  template void StreamedVCycle<T>::exchange_fold_rows(int, int, std::vector<T>&);                   \
  template void StreamedVCycle<T>::add_fold_sums(int, int, const std::vector<T>&, int);
GDP_INSTANTIATE(float)
GDP_INSTANTIATE(double)
#undef GDP_INSTANTIATE

}  // namespace gdp::bands
