// A streamed V-cycle's level below the bands: gathered to worker 0 and solved in-core, the cycle's sums added in band order.
#include <cmath>

#include "bands/streamed_vcycle_parts.h"

namespace gdp::bands {

using multigrid::Plane;

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
  std::vector<Plane<T>> weights;
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

template void StreamedVCycle<float>::run_tail();
template void StreamedVCycle<double>::run_tail();

}  // namespace gdp::bands
