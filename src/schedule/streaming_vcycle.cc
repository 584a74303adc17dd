// Streaming V-cycle: per-level rings of rows, sweeps pipelined two rows apart, levels in lockstep.
#include "schedule/streaming_vcycle.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace gdp::schedule {

using multigrid::LevelOperator;
using multigrid::Plane;
using multigrid::Columns;
using multigrid::Window;

template <class T>
struct StreamingVCycle<T>::Level {
  const LevelOperator<T>* op = nullptr;
  int width = 0, height = 0, ring = 0;
  std::vector<T> u, b, w, d;  // ring slots: u and b hold channels * width samples, w and d width samples
  multigrid::Scratch<T> scratch;
  std::vector<Stage> stages;
  std::vector<int> done;     // rows finished by each stage in this pass
  int arrived = 0;           // rows that entered this pass
  int zeroed = 0;            // restriction pass: rows whose b and w slots are cleared for accumulation
  int next_complete = 0;     // restriction pass: coarser rows completed (pushed) by this level
  int needed_from = 0;       // prolongation pass: lowest row the finer level still reads
  std::vector<int> last_touch;  // per coarser row, the last row of this level restricted into it
  std::unique_ptr<RowStore<T>> u_store, b_store, w_store, d_store;
  bool inputs_stored = false;  // level 0: b, w and d were stored by the first cycle
  std::vector<double> rr, dots;  // per channel, this cycle
};

template <class T>
StreamingVCycle<T>::StreamingVCycle(const multigrid::Operators<T>& ops, const Settings& settings)
    : ops_(ops), set_(settings) {
  const int count = ops.count(), channels = set_.channels;
  if (set_.incore_from < 1 || set_.incore_from >= count)
    throw std::logic_error(fmt::format("streaming needs 1 <= incore_from < {}, got {}", count, set_.incore_from));
  const auto& geo = ops.hierarchy->levels;
  for (int l = 0; l < set_.incore_from; ++l) {
    auto L = std::make_unique<Level>();
    const LevelOperator<T>& op = ops.levels[l];
    L->op = &op;
    L->width = op.width;
    L->height = op.height;
    for (int j = 0; j < op.height; ++j)
      for (int d = 0; d < 5; ++d)
        if (op.row_of(j, d) >= 0 && std::abs(op.row_of(j, d) - j) > 2)
          throw std::logic_error("streaming needs every row's neighbours within two rows");
    L->ring = 2 * (set_.sweeps + 2) + 8;
    const std::size_t slot = static_cast<std::size_t>(channels) * op.width;
    L->u.assign(L->ring * slot, T(0));
    L->b.assign(L->ring * slot, T(0));
    if (set_.weights) L->w.assign(static_cast<std::size_t>(L->ring) * op.width, T(0));
    if (set_.diagonal) L->d.assign(static_cast<std::size_t>(L->ring) * op.width, T(0));
    L->last_touch.assign(geo[l + 1].height(), -1);
    for (int j = 0; j < op.height; ++j)
      for (int i : geo[l + 1].py.rows[j].index) L->last_touch[i] = std::max(L->last_touch[i], j);
    const std::string name = fmt::format("level{}", l);
    L->u_store = std::make_unique<RowStore<T>>(set_.stores, slot, op.height, name + "-u");
    L->b_store = std::make_unique<RowStore<T>>(set_.stores, slot, op.height, name + "-b");
    if (l == 0 && set_.weights && set_.more_cycles)
      L->w_store = std::make_unique<RowStore<T>>(set_.stores, op.width, op.height, name + "-w");
    if (set_.diagonal) {  // never as half floats: pinned pixels' entries exceed their range
      StorePolicy exact = set_.stores;
      exact.encoding = StoreEncoding::Native;
      L->d_store = std::make_unique<RowStore<T>>(exact, op.width, op.height, name + "-d");
    }
    levels_.push_back(std::move(L));
  }
  const LevelOperator<T>& first = ops.levels[set_.incore_from];
  tail_u_.assign(channels, Plane<T>(first.width, first.height));
  tail_b_.assign(channels, Plane<T>(first.width, first.height));
  if (set_.weights) tail_w_ = Plane<T>(first.width, first.height);
  if (set_.diagonal) tail_d_ = Plane<T>(first.width, first.height);
  tail_ = std::make_unique<multigrid::InCoreVCycle<T>>(ops, set_.sweeps, set_.coarse_tolerance, set_.incore_from);
  r_.resize(ops.levels[0].width);
  probes_.resize(channels);
}

template <class T>
StreamingVCycle<T>::~StreamingVCycle() = default;

template <class T>
T* StreamingVCycle<T>::u_row(int l, int c, int j) {
  Level& L = *levels_[l];
  return L.u.data() + (static_cast<std::size_t>(j % L.ring) * set_.channels + c) * L.width;
}
template <class T>
T* StreamingVCycle<T>::b_row(int l, int c, int j) {
  Level& L = *levels_[l];
  return L.b.data() + (static_cast<std::size_t>(j % L.ring) * set_.channels + c) * L.width;
}
template <class T>
T* StreamingVCycle<T>::w_row(int l, int j) {
  Level& L = *levels_[l];
  return L.w.data() + static_cast<std::size_t>(j % L.ring) * L.width;
}

template <class T>
T* StreamingVCycle<T>::d_row(int l, int j) {
  Level& L = *levels_[l];
  return L.d.empty() ? nullptr : L.d.data() + static_cast<std::size_t>(j % L.ring) * L.width;
}

template <class T>
Window<T> StreamingVCycle<T>::window(int l, int c, int j) {
  const LevelOperator<T>& op = *levels_[l]->op;
  Window<T> w;
  for (int d = 0; d < 5; ++d) w.rows[d] = op.row_of(j, d) < 0 ? nullptr : u_row(l, c, op.row_of(j, d));
  return w;
}

template <class T>
void StreamingVCycle<T>::begin_cycle() {
  ++cycle_;
  prolongation_ = false;
  const int channels = set_.channels;
  for (int l = 0; l < static_cast<int>(levels_.size()); ++l) {
    Level& L = *levels_[l];
    L.arrived = L.zeroed = L.next_complete = L.needed_from = 0;
    L.stages.clear();
    if (l == 0 && set_.measure_initial && cycle_ == 1) L.stages.push_back(Stage::MeasureInitial);
    L.stages.insert(L.stages.end(), set_.sweeps, Stage::Sweep);
    L.stages.push_back(Stage::Restrict);
    L.done.assign(L.stages.size(), 0);
    L.rr.assign(channels, 0.0);
    L.dots.assign(channels, 0.0);
    L.u_store->clear();
    for (RowStore<T>* store : {L.b_store.get(), L.w_store.get(), L.d_store.get()}) {
      if (!store) continue;
      if (l == 0 && L.inputs_stored) store->rewind();
      else store->clear();
    }
  }
  for (Plane<T>& p : tail_b_) std::fill(p.data.begin(), p.data.end(), T(0));
  std::fill(tail_w_.data.begin(), tail_w_.data.end(), T(0));
  std::fill(tail_d_.data.begin(), tail_d_.data.end(), T(0));
  initial_rr_.assign(channels, 0.0);
  final_rr_.assign(channels, 0.0);
  for (auto& p : probes_) p = {};
}

template <class T>
void StreamingVCycle<T>::check_slot(int l, int row) const {
  const Level& L = *levels_[l];
  int live = *std::min_element(L.done.begin(), L.done.end()) - 2;
  if (prolongation_) live = std::min(live, L.needed_from);
  if (row - L.ring >= live)
    throw std::logic_error(fmt::format("streaming ring overrun on level {} at row {}", l, row));
}

template <class T>
void StreamingVCycle<T>::push(std::span<const T> u, std::span<const T> b, std::span<const T> w,
                              std::span<const T> d) {
  Level& L = *levels_[0];
  const int r = L.arrived;
  const std::size_t slot = static_cast<std::size_t>(set_.channels) * L.width;
  if (prolongation_ || r >= L.height) throw std::logic_error("StreamingVCycle::push after the last row");
  check_slot(0, r);
  std::copy(u.begin(), u.end(), u_row(0, 0, r));
  if (L.inputs_stored) {
    L.b_store->read({b_row(0, 0, r), slot});
    if (L.w_store) L.w_store->read({w_row(0, r), static_cast<std::size_t>(L.width)});
    if (L.d_store) L.d_store->read({d_row(0, r), static_cast<std::size_t>(L.width)});
  } else {
    std::copy(b.begin(), b.end(), b_row(0, 0, r));
    if (set_.weights) std::copy(w.begin(), w.end(), w_row(0, r));
    if (set_.diagonal) std::copy(d.begin(), d.end(), d_row(0, r));
  }
  ++L.arrived;
  advance(0);
}

template <class T>
void StreamingVCycle<T>::advance(int l) {
  Level& L = *levels_[l];
  int previous = L.arrived;
  for (std::size_t s = 0; s < L.stages.size(); ++s) {
    // A stage may take row j once the stage before it has finished row j + 2 (or all rows).
    const int limit = previous >= L.height ? L.height : previous - 2;
    while (L.done[s] < limit) {
      run_stage(l, L.stages[s], L.done[s]);
      ++L.done[s];
    }
    previous = L.done[s];
  }
}

template <class T>
void StreamingVCycle<T>::run_stage(int l, Stage stage, int j) {
  Level& L = *levels_[l];
  const LevelOperator<T>& op = *L.op;
  if (stage == Stage::Restrict) return restrict_into_coarser(l, j);
  const Columns whole = Columns::whole(op.width, op.periodic_x);
  for (int c = 0; c < set_.channels; ++c) {
    const Window<T> rows = window(l, c, j);
    if (stage == Stage::Sweep) {
      multigrid::relax(op, j, rows, whole, u_row(l, c, j), b_row(l, c, j), L.scratch, d_row(l, j));
    } else {
      multigrid::residual(op, j, rows, whole, b_row(l, c, j), r_.data(), L.scratch, d_row(l, j));
      (stage == Stage::MeasureInitial ? initial_rr_ : final_rr_)[c] += multigrid::row_dot(r_.data(), r_.data(), L.width);
    }
  }
}

template <class T>
void StreamingVCycle<T>::restrict_into_coarser(int l, int j) {
  Level& L = *levels_[l];
  const LevelOperator<T>& op = *L.op;
  const multigrid::LevelGeometry& g = ops_.hierarchy->levels[l + 1];
  const fem::ProlongationRow& py = g.py.rows[j];
  const bool tail = l + 1 == set_.incore_from;
  const std::size_t slot = static_cast<std::size_t>(set_.channels) * L.width;
  if (!tail) {  // clear the coarse rows this row is the first to reach
    Level& C = *levels_[l + 1];
    for (; C.zeroed <= std::max(py.index[0], py.index[1]); ++C.zeroed) {
      check_slot(l + 1, C.zeroed);
      std::fill_n(b_row(l + 1, 0, C.zeroed), static_cast<std::size_t>(set_.channels) * C.width, T(0));
      if (set_.weights) std::fill_n(w_row(l + 1, C.zeroed), C.width, T(0));
      if (set_.diagonal) std::fill_n(d_row(l + 1, C.zeroed), C.width, T(0));
    }
  }
  const auto coarse_b = [&](int c, int row) { return tail ? tail_b_[c].row(row) : b_row(l + 1, c, row); };
  const Columns coarse = Columns::whole(g.width(), op.periodic_x);
  const auto transfer = [&](const T* fine, T* coarse0, T* coarse1) {
    multigrid::restrict_rows(g.px, py, fine, 0, coarse, coarse0, coarse1, {0, 0}, L.scratch);
  };
  for (int c = 0; c < set_.channels; ++c) {
    multigrid::residual(op, j, window(l, c, j), Columns::whole(op.width, op.periodic_x), b_row(l, c, j), r_.data(),
                        L.scratch, d_row(l, j));
    L.rr[c] += multigrid::row_dot(r_.data(), r_.data(), L.width);
    transfer(r_.data(), coarse_b(c, py.index[0]), coarse_b(c, py.index[1]));
    if (set_.weights) L.dots[c] += multigrid::row_dot(w_row(l, j), u_row(l, c, j), L.width);
  }
  if (set_.weights) {
    const auto coarse_w = [&](int row) { return tail ? tail_w_.row(row) : w_row(l + 1, row); };
    transfer(w_row(l, j), coarse_w(py.index[0]), coarse_w(py.index[1]));
  }
  if (set_.diagonal) {
    const auto coarse_d = [&](int row) { return tail ? tail_d_.row(row) : d_row(l + 1, row); };
    transfer(d_row(l, j), coarse_d(py.index[0]), coarse_d(py.index[1]));
  }
  L.u_store->append({u_row(l, 0, j), slot});
  if (!L.inputs_stored) {
    L.b_store->append({b_row(l, 0, j), slot});
    if (L.w_store) L.w_store->append({w_row(l, j), static_cast<std::size_t>(L.width)});
    if (L.d_store) L.d_store->append({d_row(l, j), static_cast<std::size_t>(L.width)});
  }
  while (L.next_complete < g.height() && L.last_touch[L.next_complete] <= j) complete_coarse_row(l);
}

template <class T>
void StreamingVCycle<T>::complete_coarse_row(int l) {
  Level& L = *levels_[l];
  const int row = L.next_complete++;
  if (l + 1 == set_.incore_from) {
    if (L.next_complete == ops_.levels[l + 1].height) run_incore();
    return;
  }
  Level& C = *levels_[l + 1];
  check_slot(l + 1, row);
  std::fill_n(u_row(l + 1, 0, row), static_cast<std::size_t>(set_.channels) * C.width, T(0));
  C.arrived = row + 1;
  advance(l + 1);
}

template <class T>
void StreamingVCycle<T>::run_incore() {
  std::vector<Plane<T>> weights;
  if (set_.weights) weights = multigrid::restrict_weights(ops_, set_.incore_from, tail_w_);
  if (set_.diagonal) {
    tail_diag_ = multigrid::restrict_weights(ops_, set_.incore_from, tail_d_);
    tail_->set_diagonal(&tail_diag_);
  }
  for (int c = 0; c < set_.channels; ++c) {
    std::fill(tail_u_[c].data.begin(), tail_u_[c].data.end(), T(0));
    multigrid::CycleProbe tail;
    tail_->run(tail_u_[c], tail_b_[c], set_.weights ? &weights : nullptr, &tail);
    multigrid::CycleProbe& p = probes_[c];
    for (const auto& L : levels_) {
      if (set_.weights) p.dots.push_back(L->dots[c]);
      p.level_norms.push_back(std::sqrt(L->rr[c]));
    }
    p.dots.insert(p.dots.end(), tail.dots.begin(), tail.dots.end());
    p.level_norms.insert(p.level_norms.end(), tail.level_norms.begin(), tail.level_norms.end());
  }
}

template <class T>
void StreamingVCycle<T>::pull(std::span<T> u) {
  if (!prolongation_) {
    if (levels_[0]->arrived != levels_[0]->height) throw std::logic_error("StreamingVCycle::pull before the last push");
    prolongation_ = true;
    levels_[0]->inputs_stored = true;  // level 0 keeps b and w; the others rewrite them every cycle
    for (auto& L : levels_) {
      L->arrived = 0;
      L->stages.assign(set_.sweeps, Stage::Sweep);
      if (L.get() == levels_[0].get() && set_.measure_final) L->stages.push_back(Stage::MeasureFinal);
      L->done.assign(L->stages.size(), 0);
      L->u_store->rewind();
      L->b_store->rewind();
      if (L->d_store) L->d_store->rewind();
    }
    levels_[0]->needed_from = 0;
  }
  Level& L = *levels_[0];
  const int j = L.needed_from;
  ensure_final(0, j);
  std::copy_n(u_row(0, 0, j), static_cast<std::size_t>(set_.channels) * L.width, u.begin());
  ++L.needed_from;
}

template <class T>
void StreamingVCycle<T>::ensure_final(int l, int row) {
  Level& L = *levels_[l];
  const auto finished = [&] { return set_.sweeps > 0 ? L.done[set_.sweeps - 1] : L.arrived; };
  while (finished() <= row) {
    const int r = L.arrived;
    check_slot(l, r);
    const std::size_t slot = static_cast<std::size_t>(set_.channels) * L.width;
    L.u_store->read({u_row(l, 0, r), slot});
    L.b_store->read({b_row(l, 0, r), slot});
    if (L.d_store) L.d_store->read({d_row(l, r), static_cast<std::size_t>(L.width)});
    const multigrid::LevelGeometry& g = ops_.hierarchy->levels[l + 1];
    const fem::ProlongationRow& py = g.py.rows[r];
    const bool tail = l + 1 == set_.incore_from;
    if (!tail) {
      levels_[l + 1]->needed_from = std::min(py.index[0], py.index[1]);
      ensure_final(l + 1, std::max(py.index[0], py.index[1]));
    }
    for (int c = 0; c < set_.channels; ++c) {
      const auto coarse = [&](int i) -> const T* { return tail ? tail_u_[c].row(i) : u_row(l + 1, c, i); };
      multigrid::prolong_rows(g.px, py, coarse(py.index[0]), coarse(py.index[1]), {0, 0}, true,
                              Columns::whole(L.width, L.op->periodic_x), u_row(l, c, r), 0, L.scratch);
    }
    ++L.arrived;
    advance(l);
  }
}

template <class T>
std::size_t StreamingVCycle<T>::store_bytes() const {
  std::size_t n = 0;
  for (const auto& L : levels_)
    for (const RowStore<T>* store : {L->u_store.get(), L->b_store.get(), L->w_store.get(), L->d_store.get()})
      n += store ? store->bytes() : 0;
  return n;
}

template <class T>
std::size_t StreamingVCycle<T>::window_bytes() const {
  std::size_t n = 0;
  for (const auto& L : levels_) n += (L->u.size() + L->b.size() + L->w.size() + L->d.size()) * sizeof(T);
  for (const auto& p : tail_u_) n += 2 * p.data.size() * sizeof(T);
  return n + (tail_w_.data.size() + tail_d_.data.size()) * sizeof(T);
}

template <class T>
void StreamingVCycle<T>::save(StateWriter& out) {
  out.put(cycle_);
  out.put(prolongation_);
  for (const auto& L : levels_) {
    for (const std::vector<T>* ring : {&L->u, &L->b, &L->w, &L->d}) out.put(*ring);
    out.put(L->stages);
    out.put(L->done);
    for (int v : {L->arrived, L->zeroed, L->next_complete, L->needed_from}) out.put(v);
    out.put(L->inputs_stored);
    out.put(L->rr);
    out.put(L->dots);
    for (RowStore<T>* store : {L->u_store.get(), L->b_store.get(), L->w_store.get(), L->d_store.get()})
      out.put(store ? store->make_durable() : std::size_t{0});
  }
  for (const auto* planes : {&tail_u_, &tail_b_})
    for (const Plane<T>& p : *planes) out.put(p.data);
  out.put(tail_w_.data);
  out.put(tail_d_.data);
  for (const multigrid::CycleProbe& p : probes_) {
    out.put(p.dots);
    out.put(p.level_norms);
  }
  out.put(initial_rr_);
  out.put(final_rr_);
}

template <class T>
void StreamingVCycle<T>::load(StateReader& in) {
  in.get(cycle_);
  in.get(prolongation_);
  for (auto& L : levels_) {
    for (std::vector<T>* ring : {&L->u, &L->b, &L->w, &L->d}) in.get_sized(*ring);
    in.get(L->stages);
    in.get(L->done);
    if (L->done.size() != L->stages.size()) throw CorruptState("stage counts differ");
    for (int* v : {&L->arrived, &L->zeroed, &L->next_complete, &L->needed_from}) in.get(*v);
    in.get(L->inputs_stored);
    in.get(L->rr);
    in.get(L->dots);
    for (RowStore<T>* store : {L->u_store.get(), L->b_store.get(), L->w_store.get(), L->d_store.get()}) {
      std::size_t bytes = 0;
      in.get(bytes);
      if (store) store->restore(bytes);
    }
  }
  for (auto* planes : {&tail_u_, &tail_b_})
    for (Plane<T>& p : *planes) in.get_sized(p.data);
  in.get_sized(tail_w_.data);
  in.get_sized(tail_d_.data);
  for (multigrid::CycleProbe& p : probes_) {
    in.get(p.dots);
    in.get(p.level_norms);
  }
  in.get(initial_rr_);
  in.get(final_rr_);
}

template class StreamingVCycle<float>;
template class StreamingVCycle<double>;

}  // namespace gdp::schedule
