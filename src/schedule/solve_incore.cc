// The in-core solve schedule: every level in memory, channels spread over threads.
#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>
#include <span>

#include <fmt/format.h>

#include "multigrid/incore_vcycle.h"
#include "multigrid/input_rows.h"
#include "schedule/parallel.h"
#include "schedule/row_store.h"
#include "schedule/solve_parts.h"

namespace gdp::schedule {
namespace {

// The channels' planes. Worker t solves channels t, t + threads, ... in one pair (u, b), made
// once, in place, their pages mapped in one call. A channel waits for its worker's planes in row
// stores (memfds: a fresh mapped page costs far more than a written unmapped one, docs/multigrid.md,
// "In-core memory on a PVM guest"), and so does an earlier channel's result for the output.
template <class T>
class ChannelPlanes {
 public:
  ChannelPlanes(const SolverOptions& opt, int w, int h, int channels, int threads)
      : w_(w), h_(h), threads_(threads), parked_u_(channels), parked_b_(channels) {
    stores_.dir = opt.temp_dir, stores_.budget = &ScratchBudget::process();
    for (int t = 0; t < threads; ++t) u_.push_back(multigrid::Plane<T>::mapped(w, h)), b_.push_back(multigrid::Plane<T>::mapped(w, h));
    for (int c = threads; c < channels; ++c) park(parked_u_, "u", c), park(parked_b_, "b", c);
  }
  multigrid::Plane<T>& u(int c) { return u_[c % threads_]; }
  multigrid::Plane<T>& b(int c) { return b_[c % threads_]; }
  // Row j of channel c's input, rows in order.
  void put(int c, int j, std::span<const T> u, std::span<const T> b) {
    if (c >= threads_) return parked_u_[c]->append(u), parked_b_[c]->append(b);
    std::copy(u.begin(), u.end(), u_[c].row(j)), std::copy(b.begin(), b.end(), b_[c].row(j));
  }
  // Channel c's worker moves on to it: the previous channel's result out of the planes, c's input in.
  void turn_to(int c) {
    RowStore<T>* result = park(parked_u_, "u", c - threads_);
    for (int j = 0; j < h_; ++j) result->append({u(c).row(j), static_cast<std::size_t>(w_)});
    load(parked_u_[c], u(c));
    load(parked_b_[c], b(c));
  }
  // Channel c's result row j, rows in order (into `buffer` when it waits in a store).
  const T* result_row(int c, int j, std::vector<T>& buffer) {
    if (!parked_u_[c]) return u(c).row(j);
    if (j == 0) parked_u_[c]->rewind();
    parked_u_[c]->read(buffer);
    return buffer.data();
  }

 private:
  RowStore<T>* park(std::vector<std::unique_ptr<RowStore<T>>>& to, const char* name, int c) {
    to[c] = std::make_unique<RowStore<T>>(stores_, w_, h_, fmt::format("incore-{}{}", name, c));
    return to[c].get();
  }
  void load(std::unique_ptr<RowStore<T>>& from, multigrid::Plane<T>& to) {
    from->rewind();
    for (int j = 0; j < h_; ++j) from->read({to.row(j), static_cast<std::size_t>(w_)});
    from.reset();
  }

  int w_, h_, threads_;
  StorePolicy stores_;
  std::vector<multigrid::Plane<T>> u_, b_;  // per worker
  std::vector<std::unique_ptr<RowStore<T>>> parked_u_, parked_b_;  // per channel, while it waits
};

}  // namespace

template <class T>
void solve_incore(GuidanceSource& source, const SolverOptions& opt, RowWriter& out, SolveSummary& summary) {
  using multigrid::Plane;
  const Problem<T> problem(source, opt, summary);
  const multigrid::Operators<T>& ops = problem.ops;
  const int w = source.width(), h = source.height(), channels = source.channels();
  const std::size_t n = static_cast<std::size_t>(channels) * w;
  summary.schedule = "in-core";

  const int cycles = opt.cycle_cap();
  const multigrid::HalfPolicy half = multigrid::half_policy(opt, source.has_weights());
  const int threads = std::clamp(opt.threads, 1, std::max(channels, 1));
  const auto t_rhs = Clock::now();
  std::vector<Plane<T>> weights, diagonal;
  ChannelPlanes<T> planes(opt, w, h, channels, threads);
  multigrid::InputRows<T> input(source, problem.hierarchy);
  {
    // The mean weights only where the mean is fixed by them (alpha == 0), else one row reused;
    // kept as one row while every row is the same.
    const bool keep_weights = ops.singular;
    multigrid::WeightRows<T> wt(w, keep_weights ? h : 1);
    Plane<T> d = Plane<T>::mapped(source.has_weights() ? w : 0, source.has_weights() ? h : 0);
    std::vector<T> ur(n), br(n);
    for (int j = 0; j < h; ++j) {
      input.next(ur, br, wt.next(),
                 {d.data.data() + static_cast<std::size_t>(j) * d.width, static_cast<std::size_t>(d.width)});
      if (keep_weights) wt.add();
      for (int c = 0; c < channels; ++c) {
        const std::size_t at = static_cast<std::size_t>(c) * w;
        planes.put(c, j, {ur.data() + at, static_cast<std::size_t>(w)}, {br.data() + at, static_cast<std::size_t>(w)});
      }
    }
    // The streamed schedule keeps the finest weights for later cycles as the policy says (0 or 1,
    // exact in half floats; rounded here all the same so that both read the same values).
    if (keep_weights) {
      Plane<T> finest = wt.take();
      if (half.rounds(0, "w") && cycles > 1) multigrid::round_to_half(finest.data.data(), finest.data.size());
      weights = multigrid::restrict_weights(ops, 0, std::move(finest));
    }
    if (source.has_weights()) diagonal = multigrid::restrict_weights(ops, 0, std::move(d));
  }
  summary.seconds_rhs = seconds_since(t_rhs);
  const multigrid::InputTotals totals = input.totals();
  summary.window_bytes = 2 * static_cast<std::size_t>(threads) * w * h * sizeof(T);

  const auto t_solve = Clock::now();
  ResidualLog log(channels, static_cast<bool>(opt.log));
  std::mutex progress_mutex;
  int cycles_done = 0;
  const auto report = [&] {
    if (!opt.progress) return;
    std::lock_guard<std::mutex> lock(progress_mutex);
    opt.progress(std::min(1.0, double(++cycles_done) / (double(channels) * cycles)));
  };
  const auto solve_channel = [&](int c, multigrid::InCoreVCycle<T>& vc, Plane<T>& u, Plane<T>& b) {
    log.set_rhs_norm(c, std::sqrt(totals.rhs_norms2[c]));
    if (cycles < 1) log.initial(c, vc.residual_norm(u, b));
    for (int k = 0; k < cycles; ++k) {
      multigrid::CycleProbe probe;
      probe.norm_before = k == 0, probe.norm_after = true;  // measured in the cycle's own passes
      vc.run(u, b, weights.empty() ? nullptr : &weights, &probe);
      if (k == 0) log.initial(c, probe.before);
      log.cycle(c, probe.after, probe);
      const double shift = mean_shift(ops.singular, totals.weighted_sums[c], totals.weight_total, probe.dots);
      if (shift != 0.0)
        for (T& v : u.data) v = static_cast<T>(static_cast<double>(v) + shift);
      // The streamed schedule carries the result to the next cycle in a store ("result").
      if (k + 1 < cycles && half.rounds("result")) multigrid::round_to_half(u.data.data(), u.data.size());
      report();
      if (log.settled(c, opt.tolerance)) break;
    }
  };
  const auto worker = [&](int t) {
    multigrid::InCoreVCycle<T> vc(ops, opt.sweeps, opt.coarse_tolerance);
    vc.set_sweeps(opt.sweeps, opt.post_sweeps);
    if (!diagonal.empty()) vc.set_diagonal(&diagonal);
    vc.set_half(&half);
    for (int c = t; c < channels; c += threads) {
      if (c >= threads) planes.turn_to(c);
      solve_channel(c, vc, planes.u(c), planes.b(c));
    }
  };
  run_workers(threads, worker);
  summary.seconds_solve = seconds_since(t_solve);
  log.finish(summary, opt);

  std::vector<float> row(n);
  std::vector<T> buffer(w);
  for (int j = 0; j < h; ++j) {
    for (int c = 0; c < channels; ++c) {
      const T* uc = planes.result_row(c, j, buffer);
      std::transform(uc, uc + w, row.begin() + static_cast<std::ptrdiff_t>(c) * w,
                     [](T v) { return static_cast<float>(v); });
    }
    out.write_row(j, row);
  }
}

template void solve_incore<float>(GuidanceSource&, const SolverOptions&, RowWriter&, SolveSummary&);
template void solve_incore<double>(GuidanceSource&, const SolverOptions&, RowWriter&, SolveSummary&);

}  // namespace gdp::schedule
