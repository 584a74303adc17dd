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
    if (b == me || !plan.sends(b)) continue;
    ByteWriter pk;
    each(plan.to[b], [&](const Piece& p) { pk.put(from(p), p.n); });
    net.send(b, tag, std::move(pk.bytes));
  }
  each(plan.from[me], [&](const Piece& p) { land(p, from(p)); });
  std::vector<T> got;
  for (int b = 0; b < net.size(); ++b) {
    if (b == me || !plan.receives(b)) continue;
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
      [&](const Piece& p) { return u_row(l, p.k, first + p.r) + (p.x - L.origin); },
      [&](const Piece& p) { return into.data() + (static_cast<std::size_t>(p.k) * 2 + p.r) * L.width + p.x; }, false);
}

// Level l's restriction across the fold into coarse row `row`: `sums` holds this band's
// contributions at the mirror image of its coarse columns (whole rows: b per channel, then w and d
// as the settings have them); each goes to the band owning the column, which adds them (its own
// first, then the others' in band order).
template <class T>
void StreamedVCycle<T>::add_fold_sums(int l, int side, const std::vector<T>& sums, int row) {
  const int m = ops_.levels[base_ + l + 1].width, corigin = origin_of(l + 1);
  exchange<T>(
      net_, levels_[l]->fold[side].sums, kFoldSums + l, parts(), 1,
      [&](const Piece& p) { return sums.data() + static_cast<std::size_t>(p.k) * m + p.x; },
      [&](const Piece& p) { return part_row(l + 1, p.k, row) + (p.x - corigin); }, true);
}

// Restriction pass: coarse row `row` of the level below is complete in every band of a group; its
// columns go to the group's owner, which pushes the merged band's row into the merged stage (u zero,
// a correction; the halo's b comes in the merged stage's strips).
template <class T>
void StreamedVCycle<T>::hand_off(int row) {
  const int tl = layout_.levels, g = layout_.group_of(band_), origin = layout_.merged->origin(0, g);
  const auto len = static_cast<std::size_t>(layout_.merged->row_length(0, g));
  Level& H = *levels_[tl];
  ++H.finished;
  std::vector<T> u(merged_ ? set_.channels * len : 0, T(0)), in(merged_ ? parts() * len : 0, T(0));
  exchange<T>(
      net_, group_plan(layout_, tl, band_, layout_.group_owner(g), layout_.group_end(g), true), kHandOff, parts(), 1,
      [&](const Piece& p) { return part_row(tl, p.k, row) + (p.x - H.origin); },
      [&](const Piece& p) { return in.data() + p.k * len + (p.x - origin); }, false);
  const auto part = [&](int k, bool has) { return has ? std::span<const T>(in.data() + k * len, len) : std::span<const T>(); };
  if (merged_)
    merged_->push(u, {in.data(), set_.channels * len}, part(set_.channels, set_.weights), part(parts() - 1, set_.diagonal));
}

// Prolongation pass: rows of the level below up to `row`, handed back by the merged stage (from the
// group's owner, each band the columns it stores) into this band's ring.
template <class T>
void StreamedVCycle<T>::take_back(int row) {
  const int tl = layout_.levels, g = layout_.group_of(band_), origin = layout_.merged->origin(0, g);
  const auto len = static_cast<std::size_t>(layout_.merged->row_length(0, g));
  Level& H = *levels_[tl];
  const FoldPlan plan = group_plan(layout_, tl, band_, layout_.group_owner(g), layout_.group_end(g), false);
  std::vector<T> got(merged_ ? set_.channels * len : 0);
  for (; H.arrived <= row; ++H.arrived) {
    const int J = H.arrived;
    if (J - H.ring >= H.needed_from)
      throw std::logic_error(fmt::format("band ring overrun on the merged level at row {}", J));
    if (merged_) merged_->pull(got);
    exchange<T>(
        net_, plan, kHandBack, set_.channels, 1, [&](const Piece& p) { return got.data() + p.k * len + (p.x - origin); },
        [&](const Piece& p) { return u_row(tl, p.k, J) + (p.x - H.origin); }, false);
  }
}

// The level below the bands: every worker's partial sums are added in band order (the same bits
// run to run), its columns of b (and w, d) go to worker 0, which solves in-core (or takes the
// merged stage's probes, added over its bands) and sends the whole correction and the probes back.
template <class T>
void StreamedVCycle<T>::run_tail() {
  const int channels = set_.channels, banded = layout_.levels, tl = base_ + banded;
  const bool whole = !layout_.merged;  // else the merged stage has solved the level below
  std::vector<double> total;  // per channel: the initial residual, then per level rr and dots
  for (int c = 0; c < channels; ++c) {
    total.push_back(initial_rr_[c]);
    for (int l = 0; l < banded; ++l) {
      total.push_back(levels_[l]->rr[c]);
      total.push_back(levels_[l]->dots[c]);
    }
  }
  sum_in_order(net_, kSums, total);
  if (whole) {  // worker 0's own part is in place already
    const auto at = [&](const Piece& p) { return part_row(banded, p.k, p.r) + p.x; };
    exchange<T>(net_, group_plan(layout_, banded, band_, 0, layout_.bands, true), kGather, parts(),
                ops_.levels[tl].height, at, at, false);
  }
  ByteWriter reply;
  std::vector<multigrid::Plane<T>> weights;
  if (band_ == 0 && whole && set_.weights) weights = multigrid::restrict_weights(ops_, tl, whole_[W][0]);
  if (band_ == 0 && whole && set_.diagonal) {
    tail_diag_ = multigrid::restrict_weights(ops_, tl, whole_[D][0]);
    tail_->set_diagonal(&tail_diag_);
  }
  for (int c = 0; c < channels && band_ == 0; ++c) {
    multigrid::CycleProbe below = whole ? multigrid::CycleProbe{} : merged_->probe(c);
    if (whole) {
      multigrid::Plane<T>& u = whole_[U][c];
      std::fill(u.data.begin(), u.data.end(), T(0));
      tail_->run(u, whole_[B][c], set_.weights ? &weights : nullptr, &below);
      reply.put(u.data.data(), u.data.size());
    }
    reply.io(below.dots);
    reply.io(below.level_norms);
  }
  ByteReader u(broadcast(net_, kGather, std::move(reply.bytes)));
  const std::size_t per_channel = 1 + 2 * static_cast<std::size_t>(banded);
  for (int c = 0; c < channels; ++c) {
    if (whole) u.get(whole_[U][c].data.data(), whole_[U][c].data.size());
    multigrid::CycleProbe& p = probes_[c];
    p = {};
    const double* sums = total.data() + c * per_channel;
    for (int l = 0; l < banded; ++l) {
      if (set_.weights) p.dots.push_back(sums[2 + 2 * l]);
      p.level_norms.push_back(std::sqrt(sums[1 + 2 * l]));
    }
    multigrid::CycleProbe below;
    u.io(below.dots);
    u.io(below.level_norms);
    p.dots.insert(p.dots.end(), below.dots.begin(), below.dots.end());
    p.level_norms.insert(p.level_norms.end(), below.level_norms.begin(), below.level_norms.end());
    initial_rr_[c] = sums[0];
  }
  u.finish();
}

#define GDP_INSTANTIATE(T)                                                        \
  template T* StreamedVCycle<T>::fold_row(int, int, int, bool);                     \
  template void StreamedVCycle<T>::exchange_fold_rows(int, int, std::vector<T>&);   \
  template void StreamedVCycle<T>::add_fold_sums(int, int, const std::vector<T>&, int); \
  template void StreamedVCycle<T>::hand_off(int);                                   \
  template void StreamedVCycle<T>::take_back(int);                                  \
  template void StreamedVCycle<T>::run_tail();
GDP_INSTANTIATE(float)
GDP_INSTANTIATE(double)
#undef GDP_INSTANTIATE

}  // namespace gdp::bands
