// What crosses a band edge besides the strips: rows and restriction sums across a spherical level's
// fold, rows handed to a merged stage and back, the level below gathered to worker 0 and solved in-core.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "bands/streamed_vcycle.h"

namespace gdp::bands {
namespace {

// A piece of an exchange across the fold: columns [x, x + n) of row r of part k.
struct Piece {
  int k, r, x;
  std::size_t n;
};

// One exchange across the fold on `tag`, of `parts` x `rows` rows: every partner b gets the
// pieces plan.to[b] (read at from(piece)); the band's own pieces and every partner's, in band
// order, land at to(piece), copied or (`add`) added.
template <class T, class From, class To>
void exchange(Transport& net, const FoldPlan& plan, int tag, int parts, int rows, From&& from, To&& to, bool add) {
  const auto each = [&](const ColumnRuns& runs, auto&& f) {
    for (int k = 0; k < parts; ++k)
      for (int r = 0; r < rows; ++r)
        for (auto [x0, x1] : runs) f(Piece{k, r, x0, static_cast<std::size_t>(x1 - x0)});
  };
  const auto land = [&](const Piece& p, const T* v) {
    T* at = to(p);
    if (!add) return static_cast<void>(std::copy_n(v, p.n, at));
    for (std::size_t i = 0; i < p.n; ++i) at[i] += v[i];
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

// The merged stage's workers: merged band g is this stage's worker 2g.
class MergedTransport : public Transport {
 public:
  MergedTransport(Transport& outer, int bands) : outer_(outer), bands_(bands) {}
  int rank() const override { return outer_.rank() / 2; }
  int size() const override { return bands_; }
  void send(int to, int tag, Bytes data) override { outer_.send(2 * to, tag + kStageTags, std::move(data)); }
  Bytes receive(int from, int tag) override { return outer_.receive(2 * from, tag + kStageTags); }
  void abort(const std::string& why) override { outer_.abort(why); }

 private:
  Transport& outer_;
  int bands_;
};

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
  const int m = ops_.levels[base_ + l + 1].width, corigin = gathered(l) ? 0 : levels_[l + 1]->origin;
  exchange<T>(
      net_, levels_[l]->fold[side].sums, kFoldSums + l, parts(), 1,
      [&](const Piece& p) { return sums.data() + static_cast<std::size_t>(p.k) * m + p.x; },
      [&](const Piece& p) { return part_row(l + 1, p.k, row) + (p.x - corigin); }, true);
}

std::unique_ptr<Transport> merged_transport(Transport& outer, int bands) {
  return std::make_unique<MergedTransport>(outer, bands);
}

// Restriction pass: coarse row `row` of the level below is complete in every band of a group; the
// group's owner puts its columns together and pushes the row into the merged stage.
template <class T>
void StreamedVCycle<T>::hand_off(int row) {
  const int tl = layout_.levels, g = layout_.group_of(band_), owner = layout_.group_owner(g);
  Level& H = *levels_[tl];
  // Band m's columns of the row, part by part (b of every channel, w, d).
  const auto pieces = [&](int m, auto&& f) {
    const int a = layout_.begin(tl, m);
    for (int k = 0; k < parts(); ++k) f(k, a, static_cast<std::size_t>(layout_.end(tl, m) - a));
  };
  const auto mine = [&](int k, int a) { return part_row(tl, k, row) + (a - H.origin); };
  ++H.finished;
  if (band_ != owner) {
    ByteWriter pk;
    pieces(band_, [&](int k, int a, std::size_t n) { pk.put(mine(k, a), n); });
    net_.send(owner, kHandOff, std::move(pk.bytes));
    return;
  }
  const BandLayout& M = *layout_.merged;
  const std::size_t len = static_cast<std::size_t>(M.row_length(0, g));
  const int origin = M.origin(0, g);
  // The merged band's row: u zero (a correction), b, w, d of the group's columns; the halo's b
  // comes in the merged stage's strips.
  std::vector<T> u(set_.channels * len, T(0)), in(parts() * len, T(0));
  const auto merged = [&](int k, int a) { return in.data() + k * len + (a - origin); };
  pieces(band_, [&](int k, int a, std::size_t n) { std::copy_n(mine(k, a), n, merged(k, a)); });
  for (int m = owner + 1; m < layout_.group_end(g); ++m) {
    ByteReader un(net_.receive(m, kHandOff));
    pieces(m, [&](int k, int a, std::size_t n) { un.get(merged(k, a), n); });
    un.finish();
  }
  const auto part = [&](int k, bool has) { return has ? std::span<const T>(in.data() + k * len, len) : std::span<const T>(); };
  merged_->push(u, {in.data(), set_.channels * len}, part(set_.channels, set_.weights), part(parts() - 1, set_.diagonal));
}

// Prolongation pass: rows of the level below up to `row`, handed back by the merged stage (its
// band's row, halo included, from the group's owner to the others), into this band's ring.
template <class T>
void StreamedVCycle<T>::take_back(int row) {
  const int tl = layout_.levels, g = layout_.group_of(band_), owner = layout_.group_owner(g);
  Level& H = *levels_[tl];
  const BandLayout& M = *layout_.merged;
  const std::size_t len = static_cast<std::size_t>(M.row_length(0, g));
  const int origin = M.origin(0, g);
  std::vector<T> got(set_.channels * len);
  for (; H.arrived <= row; ++H.arrived) {
    const int J = H.arrived;
    if (J - H.ring >= H.needed_from)
      throw std::logic_error(fmt::format("band ring overrun on the merged level at row {}", J));
    if (band_ == owner) {
      merged_->pull(got);
      ByteWriter pk;
      pk.put(got.data(), got.size());
      for (int m = owner + 1; m < layout_.group_end(g); ++m) net_.send(m, kHandBack, pk.bytes);
    } else {
      ByteReader un(net_.receive(owner, kHandBack));
      un.get(got.data(), got.size());
      un.finish();
    }
    for (int c = 0; c < set_.channels; ++c)
      std::copy_n(got.data() + c * len + (H.origin - origin), H.len, u_row(tl, c, J));
  }
}

// The pieces of the gathered level that `band` contributes: its columns of every row of b (each
// channel), of w and of d, as (row pointer, count), in one order for sender and receiver.
template <class T>
template <class F>
void StreamedVCycle<T>::tail_parts(int band, F&& f) {
  const int tl = layout_.levels, th = ops_.levels[base_ + tl].height;
  const int a = layout_.begin(tl, band);
  const auto n = static_cast<std::size_t>(layout_.end(tl, band) - a);
  for (int k = 0; k < parts(); ++k)
    for (int row = 0; row < th; ++row) f(part_row(tl, k, row) + a, n);
}

// The level below the bands: every worker's partial sums are added in band order (the same bits
// run to run), its columns of b (and w, d) go to worker 0, which solves in-core and sends the
// whole correction and the level's probes back.
template <class T>
void StreamedVCycle<T>::run_tail() {
  const int channels = set_.channels, banded = layout_.levels;
  const bool whole = !layout_.merged;  // else the merged stage has solved the level below
  // Per channel: the initial residual, then per level rr and dots.
  std::vector<double> total;
  for (int c = 0; c < channels; ++c) {
    total.push_back(initial_rr_[c]);
    for (int l = 0; l < banded; ++l) {
      total.push_back(levels_[l]->rr[c]);
      total.push_back(levels_[l]->dots[c]);
    }
  }
  sum_in_order(net_, kSums, total);
  if (whole) {  // worker 0's own part is in place already
    ByteWriter mine;
    if (band_ != 0) tail_parts(band_, [&](const T* row, std::size_t n) { mine.put(row, n); });
    std::vector<Bytes> parts = gather(net_, kGather, std::move(mine.bytes));
    for (int b = 1; b < static_cast<int>(parts.size()); ++b) {
      ByteReader u(std::move(parts[b]));
      tail_parts(b, [&](T* row, std::size_t n) { u.get(row, n); });
      u.finish();
    }
  }
  ByteWriter reply;
  if (band_ == 0) solve_tail(reply);
  ByteReader u(broadcast(net_, kGather, std::move(reply.bytes)));
  const std::size_t per_channel = 1 + 2 * static_cast<std::size_t>(banded);
  for (int c = 0; c < channels; ++c) {
    if (whole) u.get(tail_u_[c].data.data(), tail_u_[c].data.size());
    multigrid::CycleProbe& p = probes_[c];
    p = {};
    const double* sums = total.data() + c * per_channel;
    for (int l = 0; l < banded; ++l) {
      if (set_.weights) p.dots.push_back(sums[2 + 2 * l]);
      p.level_norms.push_back(std::sqrt(sums[1 + 2 * l]));
    }
    std::vector<double> dots, norms;  // the levels below
    u.io(dots);
    u.io(norms);
    p.dots.insert(p.dots.end(), dots.begin(), dots.end());
    p.level_norms.insert(p.level_norms.end(), norms.begin(), norms.end());
    initial_rr_[c] = sums[0];
  }
  u.finish();
}

// Worker 0: every channel's correction and probe of the levels below, solved in-core (or the
// merged stage's, added over its bands), into `reply`.
template <class T>
void StreamedVCycle<T>::solve_tail(ByteWriter& reply) {
  const int tl = base_ + layout_.levels;
  const bool whole = !layout_.merged;
  std::vector<multigrid::Plane<T>> weights;
  if (whole && set_.weights) weights = multigrid::restrict_weights(ops_, tl, tail_w_);
  if (whole && set_.diagonal) {
    tail_diag_ = multigrid::restrict_weights(ops_, tl, tail_d_);
    tail_->set_diagonal(&tail_diag_);
  }
  for (int c = 0; c < set_.channels; ++c) {
    multigrid::CycleProbe tail;
    if (whole) {
      std::fill(tail_u_[c].data.begin(), tail_u_[c].data.end(), T(0));
      tail_->run(tail_u_[c], tail_b_[c], set_.weights ? &weights : nullptr, &tail);
      reply.put(tail_u_[c].data.data(), tail_u_[c].data.size());
    } else {
      tail = merged_->probe(c);
    }
    reply.io(tail.dots);
    reply.io(tail.level_norms);
  }
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
