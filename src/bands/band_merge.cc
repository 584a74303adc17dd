// Band V-cycle into a merged stage: restricted rows handed to each group's owner, corrected rows handed back.
#include <algorithm>

#include <fmt/format.h>

#include "bands/streamed_vcycle_parts.h"

namespace gdp::bands {
namespace {

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

std::unique_ptr<Transport> merged_transport(Transport& outer, int bands) {
  return std::make_unique<MergedTransport>(outer, bands);
}

// Restriction pass: coarse row `row` of the level below is complete in every band of a group; the
// group's owner puts its columns together and pushes the row into the merged stage.
template <class T>
void StreamedVCycle<T>::hand_off(int row) {
  const int tl = layout_.levels, g = layout_.group_of(band_), owner = layout_.group_owner(g);
  Level& H = *levels_[tl];
  // Band m's columns of the row, piece by piece: f(kind, channel, first column, count) for b of
  // every channel (kind 0), then w (1) and d (2) where the settings have them.
  const auto pieces = [&](int m, auto&& f) {
    const int a = layout_.begin(tl, m);
    const auto n = static_cast<std::size_t>(layout_.end(tl, m) - a);
    for (int c = 0; c < set_.channels; ++c) f(0, c, a, n);
    if (set_.weights) f(1, 0, a, n);
    if (set_.diagonal) f(2, 0, a, n);
  };
  const auto mine = [&](int kind, int c, int a) {
    T* r = kind == 0 ? b_row(tl, c, row) : kind == 1 ? w_row(tl, row) : d_row(tl, row);
    return r + (a - H.origin);
  };
  ++H.finished;
  if (band_ != owner) {
    Packer pk;
    pieces(band_, [&](int kind, int c, int a, std::size_t n) { pk.put(mine(kind, c, a), n); });
    net_.send(owner, kHandOff, std::move(pk.bytes));
    return;
  }
  const BandLayout& M = *layout_.merged;
  const std::size_t len = static_cast<std::size_t>(M.row_length(0, g));
  const int origin = M.origin(0, g);
  // The merged band's row: u zero (a correction), b, w, d of the group's columns; the halo's b
  // comes in the merged stage's strips.
  std::vector<T> u(set_.channels * len, T(0)), b(set_.channels * len, T(0)), w(set_.weights ? len : 0, T(0)),
      d(set_.diagonal ? len : 0, T(0));
  const auto merged = [&](int kind, int c, int a) {
    T* r = kind == 0 ? b.data() + c * len : kind == 1 ? w.data() : d.data();
    return r + (a - origin);
  };
  pieces(band_, [&](int kind, int c, int a, std::size_t n) { std::copy_n(mine(kind, c, a), n, merged(kind, c, a)); });
  for (int m = owner + 1; m < layout_.group_end(g); ++m) {
    const Bytes bytes = net_.receive(m, kHandOff);
    Unpacker un(bytes);
    pieces(m, [&](int kind, int c, int a, std::size_t n) { un.get(merged(kind, c, a), n); });
    un.finish();
  }
  merged_->push(u, b, w, d);
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
      Packer pk;
      pk.put(got.data(), got.size());
      for (int m = owner + 1; m < layout_.group_end(g); ++m) net_.send(m, kHandBack, pk.bytes);
    } else {
      const Bytes bytes = net_.receive(owner, kHandBack);
      Unpacker un(bytes);
      un.get(got.data(), got.size());
      un.finish();
    }
    for (int c = 0; c < set_.channels; ++c)
      std::copy_n(got.data() + c * len + (H.origin - origin), H.len, u_row(tl, c, J));
  }
}

template void StreamedVCycle<float>::hand_off(int);
template void StreamedVCycle<float>::take_back(int);
template void StreamedVCycle<double>::hand_off(int);
template void StreamedVCycle<double>::take_back(int);

}  // namespace gdp::bands
