// A streamed V-cycle's state for checkpoints: rings, counters, the whole level below, stores' lengths.
#include "bands/streamed_vcycle_parts.h"
#include "schedule/cycle_worker.h"

namespace gdp::bands {

using schedule::CorruptState;
using schedule::RowStore;

// Written (ByteWriter) and read back (ByteReader) by the same steps.
template <class T>
template <class Archive>
void StreamedVCycle<T>::state(Archive& a) {
  for (int* v : {&cycle_, &pulled_}) a.io(*v);
  a.io(prolongation_);
  for (auto& L : levels_) {
    for (std::vector<T>* ring : {&L->u, &L->b, &L->w, &L->d, &L->fold[0].rows, &L->fold[1].rows}) a.io_sized(*ring);
    for (int* v : {&L->arrived, &L->next_phase, &L->finished, &L->zeroed, &L->next_complete, &L->needed_from})
      a.io(*v);
    a.io(L->inputs_stored);
    a.io(L->rr);
    a.io(L->dots);
    for (RowStore<T>* store : L->stores()) schedule::store_state(a, store);
  }
  for (auto* planes : {&tail_u_, &tail_b_})
    for (multigrid::Plane<T>& p : *planes) a.io_sized(p.data);
  for (std::vector<T>* v : {&tail_w_.data, &tail_d_.data, &initial_, &initial_fold_[0], &initial_fold_[1]})
    a.io_sized(*v);
  for (multigrid::CycleProbe& p : probes_) {
    a.io(p.dots);
    a.io(p.level_norms);
  }
  a.io(initial_rr_);
  a.io(final_rr_);
  bool merged = static_cast<bool>(merged_);
  a.io(merged);
  if (merged != static_cast<bool>(merged_)) throw CorruptState("the merged stage differs");
  if (merged_) merged_->state(a);
}

template <class T>
void StreamedVCycle<T>::saved() {
  all_gather(net_, kSaved, {});
}

template void StreamedVCycle<float>::state(schedule::ByteWriter&);
template void StreamedVCycle<float>::state(schedule::ByteReader&);
template void StreamedVCycle<double>::state(schedule::ByteWriter&);
template void StreamedVCycle<double>::state(schedule::ByteReader&);
template void StreamedVCycle<float>::saved();
template void StreamedVCycle<double>::saved();

}  // namespace gdp::bands
