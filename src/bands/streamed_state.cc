// A streamed V-cycle's state for checkpoints: rings, counters, the whole level below, stores' lengths.
#include "bands/streamed_vcycle_parts.h"

namespace gdp::bands {

using schedule::CorruptState;
using schedule::RowStore;

template <class T>
void StreamedVCycle<T>::save(schedule::StateWriter& out) {
  for (int v : {cycle_, pulled_}) out.put(v);
  out.put(prolongation_);
  for (const auto& L : levels_) {
    for (const std::vector<T>* ring : {&L->u, &L->b, &L->w, &L->d, &L->fold[0].rows, &L->fold[1].rows}) out.put(*ring);
    for (int v : {L->arrived, L->next_phase, L->finished, L->zeroed, L->next_complete, L->needed_from}) out.put(v);
    out.put(L->inputs_stored);
    out.put(L->rr);
    out.put(L->dots);
    for (RowStore<T>* store : {L->u_store.get(), L->b_store.get(), L->w_store.get(), L->d_store.get()})
      out.put(store ? store->make_durable() : std::size_t{0});
  }
  for (const auto* planes : {&tail_u_, &tail_b_})
    for (const multigrid::Plane<T>& p : *planes) out.put(p.data);
  for (const std::vector<T>* v : {&tail_w_.data, &tail_d_.data, &initial_, &initial_fold_[0], &initial_fold_[1]})
    out.put(*v);
  for (const multigrid::CycleProbe& p : probes_) {
    out.put(p.dots);
    out.put(p.level_norms);
  }
  out.put(initial_rr_);
  out.put(final_rr_);
  out.put(static_cast<bool>(merged_));
  if (merged_) merged_->save(out);
}

template <class T>
void StreamedVCycle<T>::load(schedule::StateReader& in) {
  for (int* v : {&cycle_, &pulled_}) in.get(*v);
  in.get(prolongation_);
  for (auto& L : levels_) {
    for (std::vector<T>* ring : {&L->u, &L->b, &L->w, &L->d, &L->fold[0].rows, &L->fold[1].rows}) in.get_sized(*ring);
    for (int* v : {&L->arrived, &L->next_phase, &L->finished, &L->zeroed, &L->next_complete, &L->needed_from})
      in.get(*v);
    in.get(L->inputs_stored);
    in.get(L->rr);
    in.get(L->dots);
    for (RowStore<T>* store : {L->u_store.get(), L->b_store.get(), L->w_store.get(), L->d_store.get()}) {
      std::size_t bytes = 0;
      in.get(bytes);
      if (store) store->restore(bytes);
      else if (bytes) throw CorruptState("a store this level does not have");
    }
  }
  for (auto* planes : {&tail_u_, &tail_b_})
    for (multigrid::Plane<T>& p : *planes) in.get_sized(p.data);
  for (std::vector<T>* v : {&tail_w_.data, &tail_d_.data, &initial_, &initial_fold_[0], &initial_fold_[1]})
    in.get_sized(*v);
  for (multigrid::CycleProbe& p : probes_) {
    in.get(p.dots);
    in.get(p.level_norms);
  }
  in.get(initial_rr_);
  in.get(final_rr_);
  bool merged = false;
  in.get(merged);
  if (merged != static_cast<bool>(merged_)) throw CorruptState("the merged stage differs");
  if (merged_) merged_->load(in);
}

template <class T>
void StreamedVCycle<T>::saved() {
  if (layout_.bands == 1) return;
  if (band_ != 0) {
    net_.send(0, kSaved, {});
    net_.receive(0, kSavedAll);
    return;
  }
  for (int b = 1; b < layout_.bands; ++b) net_.receive(b, kSaved);
  for (int b = 1; b < layout_.bands; ++b) net_.send(b, kSavedAll, {});
}

template void StreamedVCycle<float>::save(schedule::StateWriter&);
template void StreamedVCycle<float>::load(schedule::StateReader&);
template void StreamedVCycle<double>::save(schedule::StateWriter&);
template void StreamedVCycle<double>::load(schedule::StateReader&);
template void StreamedVCycle<float>::saved();
template void StreamedVCycle<double>::saved();

}  // namespace gdp::bands
