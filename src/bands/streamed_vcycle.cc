// Streamed V-cycle: tiled sweeps per level in phases, strips once a phase, checkpoint state (more: streamed_exchange.cc).
#include "bands/streamed_vcycle.h"

#include <algorithm>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

#include "bands/band_phase.h"
#include "util/overloaded.h"

namespace gdp::bands {

using multigrid::Columns;
using multigrid::Window;
using util::Overloaded;  // one visitor of held()'s parts, a lambda per kind

template <class T>
StreamedVCycle<T>::StreamedVCycle(const multigrid::Operators<T>& ops, const BandLayout& layout, Transport& transport,
                          const CycleSettings& settings)
    : ops_(ops),
      layout_(layout),
      post_layout_(layout.post_pass()),
      net_(transport),
      set_(settings),
      band_(transport.rank()),
      base_(layout.first_level) {
  if (transport.size() != layout.bands)
    throw std::logic_error(fmt::format("{} workers for {} bands", transport.size(), layout.bands));
  for (int l = 0; l <= layout.levels; ++l) levels_.push_back(make_level(l));
  if (layout.merged && band_ == layout.group_owner(layout.group_of(band_))) {
    merged_net_ = std::make_unique<Transport>(transport.every_other(layout.merged->bands, kStageTags));
    merged_ = std::make_unique<StreamedVCycle<T>>(ops, *layout.merged, *merged_net_, set_);
  } else if (!layout.merged && band_ == 0) {
    tail_ = std::make_unique<multigrid::InCoreVCycle<T>>(ops, layout.sweeps, set_.coarse_tolerance, base_ + layout.levels);
    tail_->set_sweeps(layout.sweeps, layout.post_sweeps);
    tail_->set_half(&set_.stores.half);  // its levels rounded as if they streamed
    tail_u_ = tail_b_ = multigrid::Plane<T>(levels_.back()->width, levels_.back()->height);
  }
  r_.resize(layout.row_length(0, band_) + 8);
  probes_.resize(set_.channels);
  if (layout.top() && set_.residuals) initial_.assign(8 * static_cast<std::size_t>(set_.channels) * levels_[0]->len, T(0));
  if (layout.top() && layout.folded && set_.residuals)
    for (auto& rows : initial_fold_) rows.assign(2 * static_cast<std::size_t>(set_.channels) * levels_[0]->width, T(0));
}

// Banded level l: its columns, ring, fold plans, restriction bookkeeping and row stores; level
// `layout.levels`: when merged, this band's columns handed to the merged stage row by row (b, w, d
// as restricted; u as handed back), a few rows deep; else the gathered level, whole rows, every row.
template <class T>
std::unique_ptr<typename StreamedVCycle<T>::Level> StreamedVCycle<T>::make_level(int l) {
  const multigrid::LevelGeometry* geo = ops_.hierarchy->levels.data() + base_;
  const multigrid::LevelOperator<T>& op = ops_.levels[base_ + l];
  // A ring of u and b (every channel), w and d (as the settings have them).
  const bool whole = l == layout_.levels && !layout_.merged;
  const int ring = whole ? op.height : l == layout_.levels ? 8 : layout_.ring_rows();
  auto L = std::make_unique<Level>();
  L->op = &op, L->width = op.width, L->height = op.height, L->ring = ring;
  L->A = layout_.begin(l, band_), L->B = layout_.end(l, band_);
  L->origin = whole ? 0 : layout_.origin(l, band_), L->len = whole ? op.width : layout_.row_length(l, band_);
  const std::size_t slots = static_cast<std::size_t>(L->ring) * L->len;
  for (int q : {U, B, W, D})
    if (has(q)) L->ring_of[q].assign(slots * per(q), T(0));
  if (l == layout_.levels) return L;
  for (int j = 0; j < op.height; ++j)
    for (int d = 0; d < 5; ++d)
      if (op.row_of(j, d) >= 0 && std::abs(op.row_of(j, d) - j) > 2)
        throw std::logic_error("bands need every row's neighbours within two rows");
  if (layout_.folded) {
    if (op.height < 4) throw std::logic_error("a folded band level needs at least 4 rows");
    for (int side = 0; side < 2; ++side) {  // the top fold (rows 0, 1), then the bottom one (rows h - 2, h - 1)
      const fem::Mirror m = side == 0 ? fem::Mirror::Top : fem::Mirror::Bottom;
      L->fold[side].reads = fold_reads(layout_, l, op.width, m, band_);
      L->fold[side].sums = fold_sums(layout_, l + 1, geo[l + 1].width(), m, band_);
      L->fold[side].rows.assign(2 * static_cast<std::size_t>(set_.channels) * op.width, T(0));
    }
  }
  L->last_touch.assign(geo[l + 1].height(), -1);
  for (int j = 0; j < op.height; ++j)
    for (int i : geo[l + 1].py.rows[j].index) L->last_touch[i] = std::max(L->last_touch[i], j);
  const std::string name = fmt::format("band{}-level{}", band_, base_ + l);
  // w only where later cycles read it back; d never as half floats (half_policy): pinned pixels'
  // entries exceed their range.
  const bool keep[4] = {true, true, l == 0 && set_.weights && set_.more_cycles && layout_.top(), set_.diagonal};
  for (int q : {U, B, W, D})
    if (keep[q])
      L->store[q] = std::make_unique<schedule::RowStore<T>>(set_.stores, per(q) * L->len, op.height, name + "-" + "ubwd"[q]);
  return L;
}

template <class T>
Columns StreamedVCycle<T>::columns(int n, int begin, int end, bool forward) const {  // the one-band plan: whole rows, forward
  return layout_.single ? Columns::whole(n, layout_.periodic) : Columns::range(n, layout_.periodic, begin, end, forward);
}
template <class T>
Window<T> StreamedVCycle<T>::window(int l, int c, int j, bool initial) {
  const Level& L = *levels_[l];
  Window<T> w;
  for (int d = 0; d < 5; ++d) {
    const int r = L.op->row_of(j, d);
    if (r < 0) continue;
    if (layout_.folded && L.op->mirror_of(j, d) != fem::Mirror::None) {  // across the fold: the whole row as last exchanged
      w.rows[d] = fold_row(l, c, r, initial);
      continue;
    }
    w.rows[d] = initial ? initial_.data() + (static_cast<std::size_t>(r % 8) * set_.channels + c) * L.len
                        : ring_row(l, U, r, c);
    w.origin[d] = L.origin;
  }
  return w;
}
template <class T>
void StreamedVCycle<T>::begin_cycle() {
  ++cycle_;
  prolongation_ = false;
  pulled_ = 0;
  const int channels = set_.channels;
  for (auto& level : levels_) {
    Level& L = *level;
    L.arrived = L.next_phase = L.finished = L.zeroed = L.next_complete = L.needed_from = 0;
    L.rr.assign(channels, 0.0);
    L.dots.assign(channels, 0.0);
    for (int q : {U, B, W, D})  // (none on the level handed to the merged stage)
      if (L.store[q] && q != U && L.inputs_stored) L.store[q]->rewind();  // level 0 only
      else if (L.store[q]) L.store[q]->clear();
  }
  if (merged_) merged_->begin_cycle();
  initial_rr_.assign(channels, 0.0);
  final_rr_.assign(channels, 0.0);
  for (auto& p : probes_) p = {};
}

template <class T>
void StreamedVCycle<T>::check_slot(int l, int row) const {
  const Level& L = *levels_[l];
  int live = L.finished;  // the strips and tiles of the phases to come read no row below it
  if (prolongation_) live = std::min(live, L.needed_from);
  if (row - L.ring >= live)
    throw std::logic_error(fmt::format("band ring overrun on level {} at row {}", l, row));
}

template <class T>
typename StreamedVCycle<T>::Slots StreamedVCycle<T>::next_row() {
  const Level& L = *levels_[0];
  const int r = L.arrived;
  if (prolongation_ || r >= L.height) throw std::logic_error("StreamedVCycle::push after the last row");
  check_slot(0, r);
  const auto given = [&](int q) { return has(q) && !L.inputs_stored ? slot_of(0, q, r) : std::span<T>{}; };
  return {slot_of(0, U, r), given(B), given(W), given(D)};
}

template <class T>
void StreamedVCycle<T>::push() {
  Level& L = *levels_[0];
  const int r = L.arrived;
  for (int q : {B, W, D})  // b, w and d of later cycles from the stores
    if (L.inputs_stored && L.store[q]) L.store[q]->read(slot_of(0, q, r));
  if (layout_.top() && cycle_ == 1 && set_.residuals) {  // the initial residual
    std::ranges::copy(slot_of(0, U, r), initial_.begin() + static_cast<std::ptrdiff_t>(r % 8) * set_.channels * L.len);
    // The rows across the fold as they start, before the residuals that read them.
    if (layout_.folded && r == 1) exchange_fold_rows(0, 0, initial_fold_[0]);
    if (layout_.folded && r == L.height - 1) exchange_fold_rows(0, 1, initial_fold_[1]);
    if (r >= 2) measure(r - 2, true, initial_rr_);
    if (r == L.height - 1)
      for (int j = std::max(0, r - 1); j < L.height; ++j) measure(j, true, initial_rr_);
  }
  ++L.arrived;
  advance(0);
}

// Runs every phase of level l whose rows have arrived. Rows across the fold (G = 1): a phase's
// sweeps of rows 0, 1, h-2 and h-1 read them as all earlier phases left them, as a whole-row
// Gauss-Seidel sweep reads its mirror image; the last exchange on each side shows the final rows
// to the restriction (or the last residual). Rows final after the phase are restricted
// (restriction pass) or measured (prolongation pass, level 0 of the top stage, where the settings
// ask for residuals).
template <class T>
void StreamedVCycle<T>::advance(int l) {
  Level& L = *levels_[l];
  const int G = layout_.phase_groups, k = plan().sweeps;
  for (int& p = L.next_phase; p < phase_count(plan(), L.height) && (p * G + G - 1 < L.arrived || L.arrived == L.height); ++p) {
    if (layout_.folded && p >= 2 && p <= 2 * k + 2) exchange_fold_rows(l, 0, L.fold[0].rows);
    if (layout_.folded && p >= L.height && p <= L.height + 2 * k) exchange_fold_rows(l, 1, L.fold[1].rows);
    plan_phase(
        plan(), l, band_, L.height, p,
        [&](const Tile& t) {
          for (int c = 0; c < set_.channels; ++c)
            multigrid::relax(*L.op, t.row, window(l, c, t.row), columns(L.width, t.lo, t.hi, t.forward),
                             ring_row(l, U, t.row, c), ring_row(l, B, t.row, c), L.scratch, ring_row(l, D, t.row));
        },
        [&](bool left) { strip(l, p, left, true); }, [&](bool left) { strip(l, p, left, false); });
    while (L.finished < L.height && final_phase(plan(), L.height, L.finished) <= p) {
      const int j = L.finished++;
      if (!prolongation_) restrict_row(l, j);
      else if (l == 0 && layout_.top() && set_.residuals) measure(j, false, final_rr_);
    }
  }
}

// The strip of phase p with the neighbour on the `left` (else right) side (band_phase.h
// strip_shape): u, then b, w and d, row by row and channel by channel, sent (`outgoing`) or received.
template <class T>
void StreamedVCycle<T>::strip(int l, int p, bool left, bool outgoing) {
  Level& L = *levels_[l];
  const int other = left ? layout_.left(band_) : layout_.right(band_);
  const StripShape s = strip_shape(plan(), l, band_, L.height, p, left, outgoing);
  ByteWriter out;
  std::optional<ByteReader> in;
  if (!outgoing) in.emplace(net_.receive(other, l));
  const auto piece = [&](T* row, const int (&cols)[2]) {
    const auto n = static_cast<std::size_t>(cols[1] - cols[0]);
    if (outgoing) out.put(row + (cols[0] - L.origin), n);
    else in->get(row + (cols[0] - L.origin), n);
  };
  for (int c = 0; c < set_.channels; ++c)
    for (int row = s.u_rows[0]; row <= s.u_rows[1]; ++row) piece(ring_row(l, U, row, c), s.u_cols);
  for (int k = 0; k < parts(); ++k)
    for (int row = s.b_rows[0]; row <= s.b_rows[1]; ++row) piece(part_row(l, k, row), s.b_cols);
  if (outgoing) net_.send(other, l, std::move(out.bytes));
  else in->finish();
}

template <class T>
void StreamedVCycle<T>::measure(int j, bool initial, std::vector<double>& rr) {
  Level& L = *levels_[0];
  for (int c = 0; c < set_.channels; ++c) {
    multigrid::residual(*L.op, j, window(0, c, j, initial), columns(L.width, L.A, L.B), ring_row(0, B, j, c), r_.data(), L.scratch,
                        ring_row(0, D, j));
    rr[c] += multigrid::row_squares(r_.data() + (L.A - L.origin), L.B - L.A);
  }
}

template <class T>
void StreamedVCycle<T>::restrict_row(int l, int j) {
  Level& L = *levels_[l];
  const multigrid::LevelGeometry& g = ops_.hierarchy->levels[base_ + l + 1];
  const fem::ProlongationRow& py = g.py.rows[j];
  Level& C = *levels_[l + 1];
  for (; C.zeroed <= std::max(py.index[0], py.index[1]); ++C.zeroed) {  // clear the coarse rows this row is the first to reach
    check_slot(l + 1, C.zeroed);
    for (int k = 0; k < parts(); ++k) std::fill_n(part_row(l + 1, k, C.zeroed), C.len, T(0));
  }
  const int own = L.A - L.origin;
  // Across the fold (the first and last rows of a spherical level) the second coarse row is read
  // mirrored: its contributions land in other bands' columns, so they collect in whole rows
  // (part k at k * m) and go to their owners below.
  const bool across = layout_.folded && py.mirror != fem::Mirror::None;
  const int m = g.width();
  std::vector<T> fold;
  if (across) fold.assign(static_cast<std::size_t>(parts()) * m, T(0));
  // b of every channel (the residual's restriction), then w and d.
  for (int k = 0; k < parts(); ++k) {
    const T* fine = part_row(l, k, j);
    if (k < set_.channels) {
      multigrid::residual(*L.op, j, window(l, k, j), columns(L.width, L.A - 2, L.B + 2), ring_row(l, B, j, k), r_.data(),
                          L.scratch, ring_row(l, D, j));
      if (set_.level_norms) L.rr[k] += multigrid::row_squares(r_.data() + own, L.B - L.A);
      fine = r_.data();
    }
    T* coarse1 = across ? fold.data() + static_cast<std::size_t>(k) * m : part_row(l + 1, k, py.index[1]);
    multigrid::restrict_rows(g.px, py, fine, L.origin, columns(m, C.A, C.B), part_row(l + 1, k, py.index[0]), coarse1,
                             {C.origin, across ? 0 : C.origin}, L.scratch);
    if (k < set_.channels && set_.weights)
      L.dots[k] += multigrid::row_dot(ring_row(l, W, j) + own, ring_row(l, U, j, k) + own, L.B - L.A);
  }
  if (across) add_fold_sums(l, py.mirror == fem::Mirror::Top ? 0 : 1, fold, py.index[1]);
  for (int q : {U, B, W, D})
    if (L.store[q] && (q == U || !L.inputs_stored)) L.store[q]->append(slot_of(l, q, j));
  // The coarse rows this row completes enter the coarser level (u zero: a correction), or the
  // merged stage; after the last one, the level below the bands is solved.
  while (L.next_complete < g.height() && L.last_touch[L.next_complete] <= j) {
    const int row = L.next_complete++;
    if (l + 1 == layout_.levels) {
      if (layout_.merged) hand(row, true);
      if (L.next_complete == g.height()) run_tail();
      continue;
    }
    check_slot(l + 1, row);
    std::ranges::fill(slot_of(l + 1, U, row), T(0));
    levels_[l + 1]->arrived = row + 1;
    advance(l + 1);
  }
}

template <class T>
void StreamedVCycle<T>::pull(std::span<T> u) {
  if (!prolongation_) {
    if (levels_[0]->arrived != levels_[0]->height) throw std::logic_error("StreamedVCycle::pull before the last push");
    prolongation_ = true;
    levels_[0]->inputs_stored = layout_.top();
    for (auto& L : levels_) {
      L->arrived = L->next_phase = L->finished = L->needed_from = 0;
      for (int q : {U, B, D})  // (the level handed to the merged stage has none: u comes back row by row)
        if (L->store[q]) L->store[q]->rewind(!set_.more_cycles);  // one V-cycle: their last read
    }
  }
  Level& L = *levels_[0];
  const int j = pulled_;
  if (j >= L.height) throw std::logic_error("StreamedVCycle::pull after the last row");
  L.needed_from = j;
  ensure_final(0, j);
  std::ranges::copy(slot_of(0, U, j), u.begin());
  if (++pulled_ == L.height && layout_.top() && set_.residuals) sum_in_order(net_, kFinal, final_rr_);
}

template <class T>
void StreamedVCycle<T>::ensure_final(int l, int row) {
  Level& L = *levels_[l];
  while (L.finished <= row) {
    const int before = L.next_phase;
    if (L.arrived < L.height) {
      const int r = L.arrived;
      check_slot(l, r);
      for (int q : {U, B, D})  // (w is not read after the restriction)
        if (L.store[q]) L.store[q]->read(slot_of(l, q, r));
      const multigrid::LevelGeometry& g = ops_.hierarchy->levels[base_ + l + 1];
      const fem::ProlongationRow& py = g.py.rows[r];
      const bool tail = l + 1 == layout_.levels && !layout_.merged;  // from the gathered level
      const int corigin = levels_[l + 1]->origin;
      levels_[l + 1]->needed_from = std::min(py.index[0], py.index[1]);
      if (l + 1 < layout_.levels) ensure_final(l + 1, std::max(py.index[0], py.index[1]));
      else if (layout_.merged) hand(std::max(py.index[0], py.index[1]), false);
      // Across the fold the second coarse row is read mirrored, from the coarse level's last
      // exchange of its rows there (the gathered level is whole anyway).
      const bool across = layout_.folded && py.mirror != fem::Mirror::None && !tail;
      for (int c = 0; c < set_.channels; ++c) {
        const T* coarse1 = across ? fold_row(l + 1, c, py.index[1]) : ring_row(l + 1, U, py.index[1], c);
        multigrid::prolong_rows(g.px, py, ring_row(l + 1, U, py.index[0], c), coarse1, {corigin, across ? 0 : corigin},
                                tail || layout_.single,
                                columns(L.width, L.origin, L.origin + L.len), ring_row(l, U, r, c), L.origin, L.scratch);
      }
      ++L.arrived;
    }
    advance(l);
    if (L.next_phase == before && L.arrived == L.height)
      throw std::logic_error(fmt::format("band level {} stalled at phase {}", l, before));
  }
}
template <class T>
template <class F>
void StreamedVCycle<T>::held(F&& f) {
  for (int* v : {&cycle_, &pulled_}) f(*v);
  f(prolongation_);
  for (auto& L : levels_) {
    for (std::vector<T>* ring : {&L->ring_of[U], &L->ring_of[B], &L->ring_of[W], &L->ring_of[D], &L->fold[0].rows, &L->fold[1].rows})
      f(std::span<T>(*ring));
    for (int* v : {&L->arrived, &L->next_phase, &L->finished, &L->zeroed, &L->next_complete, &L->needed_from}) f(*v);
    f(L->inputs_stored);
    for (std::vector<double>* sums : {&L->rr, &L->dots}) f(*sums);
    for (auto& store : L->store) f(store.get());
  }
  for (std::vector<T>* v : {&initial_, &initial_fold_[0], &initial_fold_[1]}) f(std::span<T>(*v));
  for (multigrid::CycleProbe& p : probes_)
    for (std::vector<double>* sums : {&p.dots, &p.level_norms}) f(*sums);
  for (std::vector<double>* sums : {&initial_rr_, &final_rr_}) f(*sums);
}

template <class T>
typename StreamedVCycle<T>::Held StreamedVCycle<T>::bytes() {
  Held n = merged_ ? merged_->bytes() : Held{};
  n.window += r_.size() * sizeof(T);
  held(Overloaded{[&](std::span<T> v) { n.window += v.size_bytes(); },
                  [&](schedule::RowStore<T>* store) { n.scratch += store ? store->bytes() : 0; }, [](auto&&) {}});
  return n;
}

// Written (ByteWriter) and read back (ByteReader) by the same steps.
template <class T>
template <class Archive>
void StreamedVCycle<T>::state(Archive& a) {
  held(Overloaded{[&](std::span<T> v) { a.io_sized(v); },
                  [&](schedule::RowStore<T>* store) { schedule::store_state(a, store); }, [&](auto& v) { a.io(v); }});
  bool merged = static_cast<bool>(merged_);
  a.io(merged);
  if (merged != static_cast<bool>(merged_)) throw schedule::CorruptState("the merged stage differs");
  if (merged_) merged_->state(a);
}

template void StreamedVCycle<float>::state(schedule::ByteWriter&);
template void StreamedVCycle<float>::state(schedule::ByteReader&);
template void StreamedVCycle<double>::state(schedule::ByteWriter&);
template void StreamedVCycle<double>::state(schedule::ByteReader&);

template class StreamedVCycle<float>;
template class StreamedVCycle<double>;

}  // namespace gdp::bands
