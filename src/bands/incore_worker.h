// One worker of the in-core schedule under the streamed driver: its channels whole in memory, one at a time.
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <functional>
#include <optional>
#include <numeric>
#include <span>
#include <vector>

#include <fmt/format.h>

#include "bands/cycle_worker.h"
#include "multigrid/incore_vcycle.h"
#include "schedule/row_store.h"
#include "schedule/scratch_budget.h"

namespace gdp::bands {

// What the in-core workers share: the mean weights' and the diagonal's pyramids, made once by the
// worker of channel 0 from the rows it was given (mark `ready` set once they are), and the count of
// V-cycles done (worker k's in mark `cycled + k`; `cycles` in all, a settled channel's left counted).
template <class T>
struct InCoreShared {
  schedule::Marks& marks;
  int ready, cycled, workers, cycles;
  std::vector<multigrid::Plane<T>> weights = {}, diagonal = {};
  // The calling thread: the V-cycles' progress, 0.5 to 1, reported there, where a Python caller's
  // Ctrl-C is seen (the input's is 0 to 0.5).
  void report(const std::function<void(double)>& progress) {
    for (int done = 1; done <= cycles; ++done) {
      marks.wait([&](std::vector<int>& m) { return std::reduce(m.begin() + cycled, m.begin() + cycled + workers, 0) >= done; });
      if (progress) progress(0.5 + 0.5 * done / cycles);
    }
  }
};

// The second thread of an in-core worker (multigrid::PassPair): each pass of a large level on a thread
// of its own (run_workers), the two following each other step by step through two marks.
class PassThreads final : public multigrid::PassPair {
 public:
  explicit PassThreads(schedule::Marks& marks) : marks_(marks), mark_(marks.add(2)) {}
  void run(int steps, const std::function<void()>& lead, const std::function<void()>& follow) override {
    steps_ = steps;
    marks_.set(mark_, 0), marks_.set(mark_ + 1, 0);
    // (One that throws lets the other run out: the worker rethrows the exception.)
    util::run_workers(2, [&](int k) { k == 0 ? lead() : follow(); },
                      [&](int k, const std::string&) { marks_.set(mark_ + k, steps); });
  }
  void ahead(int steps) override { marks_.set(mark_, steps); }
  void done(int steps) override { marks_.set(mark_ + 1, steps); }
  void wait_done(int steps) override {
    const int until = std::min(steps - 1 + 2 * kDoneEvery, steps_ - kDoneEvery);  // (said by the pass's end)
    marks_.wait(mark_ + 1, mark_ + 2, steps - 1, std::max(steps - 1, until));
  }
  // Once it must wait, until a few steps more are done (woken once every few steps, not once a step).
  void behind(int step) override { marks_.wait(mark_, mark_ + 1, step, std::min(step + kAhead, steps_ - 1)); }

 private:
  static constexpr int kAhead = 4;
  schedule::Marks& marks_;
  const int mark_;
  int steps_ = 0;
};

// Channels [c0, c0 + n): every row in (rows.input), then each channel solved by an InCoreVCycle on
// every level, V-cycles until opt's count or tolerance, each result shifted to keep the input's mean
// (alpha == 0), then the result rows out (rows.result). One plane u, made once, in place, its pages
// mapped a few rows a call (on the second thread while the input comes in, where the worker has two);
// the other channels' u and every b in row stores (memfds, or O_DIRECT files from
// ScratchBudget::direct_from() on: a fresh mapped page costs far more, docs/multigrid.md, "In-core
// memory on a PVM guest"; the V-cycle reads b row by row), and so does an earlier channel's result.
template <class T>
class InCoreWorker {
 public:
  InCoreWorker(const multigrid::Operators<T>& ops, const SolverOptions& opt, const CycleSettings& s, int c0, int n,
               schedule::ResidualLog& log, InCoreShared<T>& shared, int k)
      : c0(c0), n(n), ops_(ops), opt_(opt), half_(s.stores.half), diagonal_(s.diagonal),
        log_(log), shared_(shared), cycled_(shared.cycled + k), w_(ops.levels[0].width), h_(ops.levels[0].height),
        u_(multigrid::Plane<T>::reserved(w_, h_)), parked_u_(n), parked_b_(n), made_(shared.marks.add(1)) {
    stores_.dir = opt.temp_dir, stores_.budget = &schedule::ScratchBudget::process();
    if (opt.threads >= 2 * shared.workers) pair_.emplace(shared.marks);
    for (int i = 0; i < n; ++i) {
      park(parked_b_, "b", i);
      if (i > 0) park(parked_u_, "u", i);
    }
  }
  std::size_t window_bytes() const { return u_.data.capacity() * sizeof(T); }

  void run() {
    // With two threads the plane and the V-cycle's levels are made (their fresh pages touched) on the
    // second while the input comes in on this one (one that throws stops the marks the input waits on).
    if (!pair_) make_planes(), read_input();
    else util::run_workers(2, [&](int k) { k == 0 ? read_input() : make_planes(); },
                           [&](int, const std::string&) { shared_.marks.stop(); });
    const multigrid::InputTotals& totals = rows.totals();
    shared_.marks.wait(shared_.ready, 0);
    multigrid::InCoreVCycle<T>& vc = *vc_;
    if (!shared_.diagonal.empty()) vc.set_diagonal(&shared_.diagonal);
    for (int i = 0; i < n; ++i) {
      if (i > 0) turn_to(i);
      solve(i, vc, totals);
    }
    std::vector<T> u(static_cast<std::size_t>(n) * w_);  // a result row (every channel)
    for (int j = 0; j < h_; ++j) {
      for (int i = 0; i < n; ++i) std::copy_n(result_row(i, j), w_, u.begin() + static_cast<std::ptrdiff_t>(i) * w_);
      rows.result(j, u);
    }
  }

  WorkerRows<T> rows;
  const int c0, n, band = 0;

 private:
  using Plane = multigrid::Plane<T>;
  using Store = std::unique_ptr<schedule::RowStore<T>>;

  // Every row in: the first channel's u into its plane, every other u and every b into its store
  // (the V-cycle reads b from there, row by row). Channel 0's worker also takes the mean weights (where the
  // mean is fixed by them, alpha == 0: kept as one row while every row is the same) and the
  // diagonal, and makes the pyramids every worker reads.
  void read_input() {
    const bool weights = c0 == 0 && ops_.singular, diagonal = c0 == 0 && diagonal_;
    multigrid::WeightRows<T> wt(w_, weights ? h_ : 0);
    Plane d = Plane::mapped(diagonal ? w_ : 0, diagonal ? h_ : 0);
    std::vector<T> u(static_cast<std::size_t>(n) * w_), b(u.size());
    for (int j = 0, made = 0; j < h_; ++j) {
      if (j >= made) shared_.marks.wait([&](std::vector<int>& m) { return (made = m[made_]) > j; });
      rows.input(j, {u, b, weights ? wt.next() : std::span<T>{},
                     {d.data.data() + static_cast<std::size_t>(j) * d.width, static_cast<std::size_t>(d.width)}});
      if (weights) wt.add();
      for (int i = 0; i < n; ++i) {
        const std::span<const T> ui(u.data() + static_cast<std::size_t>(i) * w_, w_), bi(b.data() + static_cast<std::size_t>(i) * w_, w_);
        parked_b_[i]->append(bi);
        if (i > 0) parked_u_[i]->append(ui);
        else std::ranges::copy(ui, u_.row(j));
      }
    }
    if (c0 != 0) return;
    // The streamed schedule keeps the finest weights for later cycles as the policy says (0 or 1,
    // exact in half floats; rounded here all the same so that both read the same values).
    if (weights) {
      Plane finest = wt.take();
      if (half_.rounds(0, "w") && opt_.cycle_cap() > 1) multigrid::round_to_half(finest.data.data(), finest.data.size());
      shared_.weights = multigrid::restrict_weights(ops_, 0, std::move(finest), true);
    }
    if (diagonal) shared_.diagonal = multigrid::restrict_weights(ops_, 0, std::move(d));
    shared_.marks.set(shared_.ready, 1);
  }

  // Local channel i's V-cycles, its b read from its store.
  void solve(int i, multigrid::InCoreVCycle<T>& vc, const multigrid::InputTotals& totals) {
    const int cycles = opt_.cycle_cap(), c = c0 + i;
    schedule::RowStore<T>& store = *parked_b_[i];
    multigrid::RowFeed<T> b{[&] { store.rewind(); }, [&](std::span<T> row) { store.read(row); }};
    log_.set_rhs_norm(c, std::sqrt(totals.rhs_norms2[c]));
    for (int k = 0; k < cycles; ++k) {
      multigrid::CycleProbe probe;
      probe.norm_before = k == 0 && opt_.measures_residuals(), probe.norm_after = opt_.measures_residuals();  // in the cycle's own passes
      probe.sum_level_norms = static_cast<bool>(opt_.log);
      vc.run(u_, b, shared_.weights.empty() ? nullptr : &shared_.weights, &probe);
      if (k == 0) log_.initial(c, probe.before);
      log_.cycle(c, probe.after, probe);
      schedule::shift_mean(std::span<T>(u_.data), schedule::mean_shift(ops_.singular, totals.weighted_sums[c],
                                                                        totals.weight_total, probe.dots));
      // The streamed schedule carries the result to the next cycle in a store ("result").
      if (k + 1 < cycles && half_.rounds("result")) multigrid::round_to_half(u_.data.data(), u_.data.size());
      // One V-cycle more done (every one left once the channel has settled); a stopped solve stops here.
      const bool settled = log_.settled(c, opt_.tolerance);
      shared_.marks.set(cycled_, done_ += settled ? cycles - k : 1);
      shared_.marks.wait(cycled_, done_ - 1);
      if (settled) break;
    }
    parked_b_[i].reset();
  }

  // The plane's rows made a few at a time (mark made_: rows made), then the V-cycle (its levels).
  void make_planes() {
    const int step = std::max<int>(1, util::kHugePage / (static_cast<std::size_t>(w_) * sizeof(T)));
    for (int j = 0; j < h_;) {
      j = std::min(j + step, h_);
      u_.make_rows(j);
      shared_.marks.set(made_, j);
    }
    vc_.emplace(ops_, opt_.sweeps, opt_.coarse_tolerance);
    vc_->set_sweeps(opt_.sweeps, opt_.post_sweeps);
    vc_->set_half(&half_);
    if (pair_) vc_->set_pair(&*pair_);
  }

  // Local channel i moves into the plane: the previous one's result out to a store as i's u comes in.
  void turn_to(int i) {
    schedule::RowStore<T>* result = park(parked_u_, "u", i - 1);
    parked_u_[i]->rewind();
    for (int j = 0; j < h_; ++j) {
      const std::span<T> row(u_.row(j), static_cast<std::size_t>(w_));
      result->append(row);
      parked_u_[i]->read(row);
    }
    parked_u_[i].reset();
  }
  // Local channel i's result row j, rows in order.
  const T* result_row(int i, int j) {
    if (!parked_u_[i]) return u_.row(j);
    if (j == 0) parked_u_[i]->rewind();
    parked_u_[i]->read(buffer_);
    return buffer_.data();
  }
  schedule::RowStore<T>* park(std::vector<Store>& to, const char* name, int i) {
    to[i] = std::make_unique<schedule::RowStore<T>>(stores_, w_, h_, fmt::format("incore-{}{}", name, c0 + i));
    return to[i].get();
  }

  const multigrid::Operators<T>& ops_;
  const SolverOptions& opt_;
  const multigrid::HalfPolicy half_;
  const bool diagonal_;
  schedule::ResidualLog& log_;
  InCoreShared<T>& shared_;
  const int cycled_;  // its mark of V-cycles done
  int done_ = 0;
  const int w_, h_;
  schedule::StorePolicy stores_;
  Plane u_;
  std::vector<Store> parked_u_, parked_b_;  // per local channel, while it waits
  std::optional<PassThreads> pair_;  // two threads a worker where the options give each two
  const int made_;  // its mark of the planes' rows made
  std::optional<multigrid::InCoreVCycle<T>> vc_;
  std::vector<T> buffer_ = std::vector<T>(w_);
};

}  // namespace gdp::bands
