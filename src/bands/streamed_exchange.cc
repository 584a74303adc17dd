// What crosses a band edge besides the strips: rows and restriction sums across a spherical level's
// fold, rows handed to a merged stage and back, the level below gathered to worker 0 and solved in-core.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "bands/streamed_vcycle.h"

namespace gdp::bands {
namespace {

// A piece of an exchange: columns [x, x + n) of row r of part k.
struct Piece {
  int k, r, x;
  std::size_t n;
};

// One exchange of column runs on `tag` (across the fold, at a merge, to the gathered level), of
// `parts` x `rows` rows: every partner b gets the pieces plan.to[b] (read at from(piece)); the
// band's own pieces and every partner's, in band order, land at to(piece), copied or (`add`) added.
template <class T, class From, class To>
void exchange(Transport& net, const FoldPlan& plan, int tag, int parts, int rows, From&& from, To&& to, bool add) {
  const auto each = [&](const ColumnRuns& runs, auto&& f) {
    for (int k = 0; k < parts; ++k)
      for (int r = 0; r < rows; ++r)
        for (auto [x0, x1] : runs) f(Piece{k, r, x0, static_cast<std::size_t>(x1 - x0)});
  };
  const auto land = [&](const Piece& p, const T* v) {
    T* at = to(p);
    if (add)
      for (std::size_t i = 0; i < p.n; ++i) at[i] += v[i];
    else if (at != v)  // (a band's own part of the gathered level is in place)
      std::copy_n(v, p.n, at);
  };
  const int me = net.rank();
  for (int b = 0; b < net.size(); ++b) {
    if (b == me || plan.to[b].empty()) continue;
    ByteWriter pk;
    each(plan.to[b], [&](const Piece& p) { pk.put(from(p), p.n); });
    net.send(b, tag, std::move(pk.bytes));
  }
  each(plan.from[me], [&](const Piece& p) { land(p, from(p)); });
  std::vector<T> got;
  for (int b = 0; b < net.size(); ++b) {
    if (b == me || plan.from[b].empty()) continue;
    ByteReader un(net.receive(b, tag));
    each(plan.from[b], [&](const Piece& p) {
      got.resize(p.n);
      un.get(add ? got.data() : to(p), p.n);
      if (add) land(p, got.data());
    });
    un.finish();
  }
}

}  // namespace

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
  const int first = side == 0 ? 0 : L.height - 2;
  exchange<T>(
      net_, L.fold[side].reads, kFoldRows + l, set_.channels, 2,
      [&](const Piece& p) { return ring_row(l, U, first + p.r, p.k) + (p.x - L.origin); },
      [&](const Piece& p) { return into.data() + (static_cast<std::size_t>(p.k) * 2 + p.r) * L.width + p.x; }, false);
}

// Level l's restriction across the fold into coarse row `row`: `sums` holds this band's
// contributions at the mirror image of its coarse columns (whole rows: b per channel, then w and d
// as the settings have them); each goes to the band owning the column, which adds them (its own
// first, then the others' in band order).
template <class T>
void StreamedVCycle<T>::add_fold_sums(int l, int side, const std::vector<T>& sums, int row) {
  const int m = levels_[l + 1]->width, corigin = levels_[l + 1]->origin;
  exchange<T>(
      net_, levels_[l]->fold[side].sums, kFoldSums + l, parts(), 1,
      [&](const Piece& p) { return sums.data() + static_cast<std::size_t>(p.k) * m + p.x; },
      [&](const Piece& p) { return part_row(l + 1, p.k, row) + (p.x - corigin); }, true);
}

// Restriction pass (`off`): coarse row `row` of the level below is complete in every band of a
// group; b, w and d of the columns each owns go to the group's owner, straight into the merged
// stage's next row (u zero: a correction; zero outside the group's columns, where the halo's b comes
// in its strips). Prolongation pass: the rows up to `row`, pulled from the merged stage, go back,
// the columns each band stores.
template <class T>
void StreamedVCycle<T>::hand(int row, bool off) {
  const int tl = layout_.levels, g = layout_.group_of(band_), parts = off ? this->parts() : set_.channels;
  Level& H = *levels_[tl];
  const Level* M = merged_ ? merged_->levels_[0].get() : nullptr;  // (on the group's owner)
  std::vector<T> back(!off && M ? parts * M->len : 0);  // a row pulled from the merged stage
  const FoldPlan plan = group_plan(layout_, tl, band_, layout_.group_owner(g), layout_.group_end(g), off);
  for (int& J = off ? H.finished : H.arrived; J <= row; ++J) {
    const auto at = [&](bool ring) {
      return [&, ring](const Piece& p) {
        if (ring) return (off ? part_row(tl, p.k, J) : ring_row(tl, U, J, p.k)) + (p.x - H.origin);
        return (off ? merged_->part_row(0, p.k, J) : back.data() + p.k * M->len) + (p.x - M->origin);
      };
    };
    if (!off && J - H.ring >= H.needed_from) throw std::logic_error(fmt::format("band ring overrun on the merged level at row {}", J));
    if (!off && M) merged_->pull(back);
    if (off && M) {  // the merged row's slots, zero until the exchange lands the group's columns
      const Slots s = merged_->next_row();
      for (std::span<T> slot : {s.u, s.b, s.w, s.d}) std::ranges::fill(slot, T(0));
    }
    exchange<T>(net_, plan, off ? kHandOff : kHandBack, parts, 1, at(off), at(!off), false);
    if (off && M) merged_->push();
  }
}

// The level below the bands: every worker's partial sums are added in band order (the same bits
// run to run), its columns of b (and w, d) go to worker 0, which solves in-core (or takes the
// merged stage's probes, added over its bands) and sends the whole correction and the probes back.
template <class T>
void StreamedVCycle<T>::run_tail() {
  const int channels = set_.channels, banded = layout_.levels, tl = base_ + banded;
  const bool whole = !layout_.merged;  // else the merged stage has solved the level below
  std::vector<double> total = initial_rr_;  // then per level rr and dots (each per channel)
  for (int l = 0; l < banded; ++l)
    for (const std::vector<double>* v : {&levels_[l]->rr, &levels_[l]->dots}) total.insert(total.end(), v->begin(), v->end());
  sum_in_order(net_, kSums, total);
  if (whole) {  // worker 0's own part is in place already
    const auto at = [&](const Piece& p) { return part_row(banded, p.k, p.r) + p.x; };
    exchange<T>(net_, group_plan(layout_, banded, band_, 0, layout_.bands, true), kGather, parts(),
                ops_.levels[tl].height, at, at, false);
  }
  ByteWriter reply;
  const int height = levels_[banded]->height, width = levels_[banded]->width;
  const auto plane = [&](int q, int c) -> multigrid::Plane<T>& {  // channel c of q as the tail reads it (in tail_b_)
    for (int j = 0; j < height; ++j) std::copy_n(ring_row(banded, q, j, c), width, tail_b_.row(j));
    return tail_b_;
  };
  std::vector<multigrid::Plane<T>> weights;
  if (band_ == 0 && whole && set_.weights) weights = multigrid::restrict_weights(ops_, tl, plane(W, 0));
  if (band_ == 0 && whole && set_.diagonal) {
    tail_diag_ = multigrid::restrict_weights(ops_, tl, plane(D, 0));
    tail_->set_diagonal(&tail_diag_);
  }
  for (int c = 0; c < channels && band_ == 0; ++c) {
    multigrid::CycleProbe below = whole ? multigrid::CycleProbe{} : merged_->probe(c);
    below.sum_level_norms = set_.level_norms;
    if (whole) {
      std::fill(tail_u_.data.begin(), tail_u_.data.end(), T(0));
      tail_->run(tail_u_, plane(B, c), set_.weights ? &weights : nullptr, &below);
      reply.put(tail_u_.data.data(), tail_u_.data.size());
    }
    reply.io(below.dots);
    reply.io(below.level_norms);
  }
  ByteReader u(broadcast(net_, kGather, std::move(reply.bytes)));
  for (int c = 0; c < channels; ++c) {
    for (int j = 0; j < height && whole; ++j) u.get(ring_row(banded, U, j, c), width);
    multigrid::CycleProbe& p = probes_[c];
    u.io(p.dots);  // the levels below the bands', which go first
    u.io(p.level_norms);
    for (int l = banded - 1; l >= 0; --l) {
      if (set_.weights) p.dots.insert(p.dots.begin(), total[(2 + 2 * l) * channels + c]);
      p.level_norms.insert(p.level_norms.begin(), std::sqrt(total[(1 + 2 * l) * channels + c]));
    }
    initial_rr_[c] = total[c];
  }
  u.finish();
}

#define GDP_INSTANTIATE(T)                                                        \
  template T* StreamedVCycle<T>::fold_row(int, int, int, bool);                     \
  template void StreamedVCycle<T>::exchange_fold_rows(int, int, std::vector<T>&);   \
  template void StreamedVCycle<T>::add_fold_sums(int, int, const std::vector<T>&, int); \
  template void StreamedVCycle<T>::hand(int, bool);                                 \
  template void StreamedVCycle<T>::run_tail();
GDP_INSTANTIATE(float)
GDP_INSTANTIATE(double)
#undef GDP_INSTANTIATE

}  // namespace gdp::bands
