// One worker thread's V-cycles, shared by the streaming lanes and the bands: rows in, cycles, mean shift, rows out.
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "gdp/solver.h"
#include "schedule/bounded_queue.h"
#include "schedule/input_rows.h"
#include "schedule/row_store.h"
#include "schedule/solve_parts.h"

namespace gdp::schedule {

constexpr std::size_t kQueued = 2;  // batches in flight per worker and direction

// Rows handed between threads at a time: about 256K samples (1 MB of floats), 1 to 16 rows.
inline int batch_rows(int length, int channels) { return std::clamp((1 << 18) / std::max(1, length * channels), 1, 16); }

// Rows first .. first + rows - 1: u and b (channels * length samples per row), w and d (length
// per row, or empty when the problem has none).
template <class T>
struct Batch {
  int first = 0, rows = 0;
  std::vector<T> u, b, w, d;
};

// Batches handed back for reuse: their vectors keep their capacity, so a solve allocates a few
// batches per worker once instead of one per batch (large buffers allocated and freed in the
// inner loop cost a page fault per page every time, docs/multigrid.md).
template <class T>
class BatchPool {
 public:
  void give(Batch<T>&& b) {
    b.first = b.rows = 0;
    for (std::vector<T>* v : {&b.u, &b.b, &b.w, &b.d}) v->clear();
    const std::lock_guard lock(mutex_);
    free_.push_back(std::move(b));
  }
  Batch<T> take() {
    const std::lock_guard lock(mutex_);
    if (free_.empty()) return {};
    Batch<T> b = std::move(free_.back());
    free_.pop_back();
    return b;
  }

 private:
  std::mutex mutex_;
  std::vector<Batch<T>> free_;
};

// Runs the V-cycles of `vcycle` (a StreamingVCycle or a bands::BandVCycle: begin_cycle, push,
// pull, probe, initial_norm, final_norm) on rows of `channels` x `length` samples: the first
// cycle's rows from the batches in `in`, later cycles' from the previous result (a row store),
// each result shifted to keep the input's mean (alpha == 0), V-cycles until `opt`'s count or
// tolerance, and the last result's columns [keep, keep + kept) out in batches.
template <class T, class VCycle>
class CycleWorker {
 public:
  CycleWorker(VCycle& vcycle, const SolverOptions& opt, bool singular, int channels, int length, int height,
              const StorePolicy& stores, const std::string& name)
      : in(kQueued), out(kQueued), vcycle_(vcycle), opt_(opt), singular_(singular), channels_(channels),
        length_(length), height_(height) {
    if (cycles() > 1)
      carry_ = std::make_unique<RowStore<T>>(stores, static_cast<std::size_t>(channels) * length, height, name);
  }
  std::size_t carry_bytes() const { return carry_ ? carry_->bytes() : 0; }

  // `totals()` gives the input's sums (InputTotals; called once every input row is pushed, it
  // may wait for them); `log` gets channels c0 .. c0 + channels - 1. Returns false when one of
  // the queues was closed (the solve was stopped).
  template <class Totals>
  bool run(Totals&& totals, ResidualLog& log, int c0, int keep, int kept) {
    keep_ = keep;
    kept_ = kept;
    const std::size_t n = static_cast<std::size_t>(channels_) * length_;
    std::vector<T> u(n);
    std::vector<double> shift(channels_);
    Batch<T> batch, result;
    int next_in = 0;  // row of `batch` to push next
    for (int k = 0; k < cycles(); ++k) {
      vcycle_.begin_cycle();
      if (carry_) carry_->rewind();
      for (int j = 0; j < height_; ++j) {
        if (k > 0) {
          carry_->read(u);
          vcycle_.push(u, {}, {});
          continue;
        }
        if (next_in == batch.rows) {
          auto b = in.pop();
          if (!b) return false;
          spent_in.give(std::move(batch));
          batch = std::move(*b);
          next_in = 0;
        }
        const std::size_t at = static_cast<std::size_t>(next_in) * n;
        const auto pixel_row = [&](const std::vector<T>& v) {
          return v.empty() ? std::span<const T>{}
                           : std::span<const T>{v.data() + static_cast<std::size_t>(next_in) * length_,
                                                static_cast<std::size_t>(length_)};
        };
        vcycle_.push({batch.u.data() + at, n}, {batch.b.data() + at, n}, pixel_row(batch.w), pixel_row(batch.d));
        ++next_in;
      }
      const InputTotals& sums = totals();
      for (int c = 0; c < channels_; ++c) {
        if (k == 0) {
          log.set_rhs_norm(c0 + c, std::sqrt(sums.rhs_norms2[c0 + c]));
          log.initial(c0 + c, vcycle_.initial_norm(c));
        }
        shift[c] = mean_shift(singular_, sums.weighted_sums[c0 + c], sums.weight_total, vcycle_.probe(c).dots);
      }
      const bool surely_last = k + 1 == cycles();
      if (carry_ && !surely_last) carry_->clear();
      for (int j = 0; j < height_; ++j) {
        vcycle_.pull(u);
        for (int c = 0; c < channels_; ++c) {
          if (shift[c] == 0.0) continue;
          T* p = u.data() + static_cast<std::size_t>(c) * length_;
          for (int i = 0; i < length_; ++i) p[i] = static_cast<T>(static_cast<double>(p[i]) + shift[c]);
        }
        if (!surely_last) carry_->append(u);
        else if (!emit(result, j, u)) return false;
      }
      bool converged = opt_.tolerance > 0.0;
      for (int c = 0; c < channels_; ++c) {
        log.cycle(c0 + c, vcycle_.final_norm(c), vcycle_.probe(c));
        converged = converged && log.last(c0 + c) <= opt_.tolerance;
      }
      if (surely_last) return true;
      if (converged) {  // the carried result is the answer (every worker sees the same sums)
        carry_->rewind();
        for (int j = 0; j < height_; ++j) {
          carry_->read(u);
          if (!emit(result, j, u)) return false;
        }
        return true;
      }
    }
    return true;
  }

  BoundedQueue<Batch<T>> in, out;
  BatchPool<T> spent_in, spent_out;  // batches of `in` and `out` the taker is done with

 private:
  int cycles() const { return opt_.cycle_cap(); }
  // The kept columns of row j into the result batch, sent when full or last; false when stopped.
  bool emit(Batch<T>& result, int j, const std::vector<T>& u) {
    if (result.rows == 0) result.first = j;
    for (int c = 0; c < channels_; ++c) {
      const T* p = u.data() + static_cast<std::size_t>(c) * length_ + keep_;
      result.u.insert(result.u.end(), p, p + kept_);
    }
    ++result.rows;
    if (result.rows < batch_rows(kept_, channels_) && j + 1 < height_) return true;
    const bool ok = out.push(std::move(result));
    result = spent_out.take();
    return ok;
  }

  VCycle& vcycle_;
  const SolverOptions& opt_;
  bool singular_;
  int channels_, length_, height_, keep_ = 0, kept_ = 0;
  std::unique_ptr<RowStore<T>> carry_;
};

}  // namespace gdp::schedule
