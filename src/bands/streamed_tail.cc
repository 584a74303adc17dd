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
  for (int c = 0; c < set_.channels; ++c)
    for (int row = 0; row < th; ++row) f(tail_b_[c].row(row) + a, n);
  if (set_.weights)
    for (int row = 0; row < th; ++row) f(tail_w_.row(row) + a, n);
  if (set_.diagonal)
    for (int row = 0; row < th; ++row) f(tail_d_.row(row) + a, n);
}

// The level below the bands: every worker's columns of b (and w) and its partial sums go to
// worker 0, which solves in-core and sends the whole correction and the cycle's sums back.
template <class T>
void StreamedVCycle<T>::run_tail() {
  const int tl = base_ + layout_.levels, channels = set_.channels, banded = layout_.levels;
  const bool whole = !layout_.merged;  // else the merged stage has solved the level below
  // This band's partial sums, per channel: the initial residual, then per level rr and dots.
  std::vector<double> sums;
  for (int c = 0; c < channels; ++c) {
    sums.push_back(initial_rr_[c]);
    for (int l = 0; l < banded; ++l) {
      sums.push_back(levels_[l]->rr[c]);
      sums.push_back(levels_[l]->dots[c]);
    }
  }
  if (band_ != 0) {
    Packer p;
    if (whole) tail_parts(band_, [&](const T* row, std::size_t n) { p.put(row, n); });
    p.put(sums.data(), sums.size());
    net_.send(0, kGather, std::move(p.bytes));
    const Bytes reply = net_.receive(0, kScatter);
    Unpacker u(reply);
    for (int c = 0; c < channels; ++c) {
      if (whole) u.get(tail_u_[c].data.data(), tail_u_[c].data.size());
      auto& probe = probes_[c];
      probe.dots.resize(static_cast<std::size_t>(u.get()));
      u.get(probe.dots.data(), probe.dots.size());
      probe.level_norms.resize(static_cast<std::size_t>(u.get()));
      u.get(probe.level_norms.data(), probe.level_norms.size());
      initial_rr_[c] = u.get();
    }
    u.finish();
    return;
  }
  // Worker 0: its own part is in place already; the others' added in band order (the same bits
  // run to run).
  std::vector<double> total = sums, part(sums.size());
  for (int b = 1; b < layout_.bands; ++b) {
    const Bytes bytes = net_.receive(b, kGather);
    Unpacker u(bytes);
    if (whole) tail_parts(b, [&](T* row, std::size_t n) { u.get(row, n); });
    u.get(part.data(), part.size());
    u.finish();
    for (std::size_t i = 0; i < total.size(); ++i) total[i] += part[i];
  }
  const std::size_t per_channel = 1 + 2 * static_cast<std::size_t>(banded);
  const auto rr = [&](int c, int l) { return total[c * per_channel + 1 + 2 * l]; };
  const auto dots = [&](int c, int l) { return total[c * per_channel + 2 + 2 * l]; };
  std::vector<Plane<T>> weights;
  if (whole && set_.weights) weights = multigrid::restrict_weights(ops_, tl, tail_w_);
  if (whole && set_.diagonal) {
    tail_diag_ = multigrid::restrict_weights(ops_, tl, tail_d_);
    tail_->set_diagonal(&tail_diag_);
  }
  Packer reply;
  for (int c = 0; c < channels; ++c) {
    multigrid::CycleProbe tail;
    if (whole) {
      std::fill(tail_u_[c].data.begin(), tail_u_[c].data.end(), T(0));
      tail_->run(tail_u_[c], tail_b_[c], set_.weights ? &weights : nullptr, &tail);
    } else {
      tail = merged_->probe(c);  // its levels' sums, added over its bands
    }
    multigrid::CycleProbe& p = probes_[c];
    p = {};
    for (int l = 0; l < banded; ++l) {
      if (set_.weights) p.dots.push_back(dots(c, l));
      p.level_norms.push_back(std::sqrt(rr(c, l)));
    }
    p.dots.insert(p.dots.end(), tail.dots.begin(), tail.dots.end());
    p.level_norms.insert(p.level_norms.end(), tail.level_norms.begin(), tail.level_norms.end());
    initial_rr_[c] = total[c * per_channel];
    if (whole) reply.put(tail_u_[c].data.data(), tail_u_[c].data.size());
    reply.put(static_cast<double>(p.dots.size()));
    reply.put(p.dots.data(), p.dots.size());
    reply.put(static_cast<double>(p.level_norms.size()));
    reply.put(p.level_norms.data(), p.level_norms.size());
    reply.put(initial_rr_[c]);
  }
  for (int b = 1; b < layout_.bands; ++b) net_.send(b, kScatter, reply.bytes);
}

template <class T>
void StreamedVCycle<T>::reduce_final() {
  const int channels = set_.channels;
  if (band_ != 0) {
    Packer p;
    p.put(final_rr_.data(), final_rr_.size());
    net_.send(0, kFinalUp, std::move(p.bytes));
    const Bytes reply = net_.receive(0, kFinalDown);
    Unpacker u(reply);
    u.get(final_rr_.data(), final_rr_.size());
    u.finish();
    return;
  }
  std::vector<double> sum(final_rr_);
  for (int b = 1; b < layout_.bands; ++b) {
    const Bytes bytes = net_.receive(b, kFinalUp);
    Unpacker u(bytes);
    std::vector<double> part(channels);
    u.get(part.data(), part.size());
    u.finish();
    for (int c = 0; c < channels; ++c) sum[c] += part[c];
  }
  final_rr_ = sum;
  for (int b = 1; b < layout_.bands; ++b) {
    Packer p;
    p.put(final_rr_.data(), final_rr_.size());
    net_.send(b, kFinalDown, std::move(p.bytes));
  }
}

template void StreamedVCycle<float>::run_tail();
template void StreamedVCycle<float>::reduce_final();
template void StreamedVCycle<double>::run_tail();
template void StreamedVCycle<double>::reduce_final();

}  // namespace gdp::bands
