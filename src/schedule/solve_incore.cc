// The in-core solve schedule: every level in memory, channels spread over threads.
#include <algorithm>
#include <cmath>
#include <mutex>

#include "multigrid/incore_vcycle.h"
#include "multigrid/input_rows.h"
#include "schedule/parallel.h"
#include "schedule/solve_parts.h"

namespace gdp::schedule {
namespace {

// A zeroed w x h plane. A large one is huge pages (Plane's util::BigVector), all mapped in one
// call before the zero fill touches them (util::populate; docs/multigrid.md, "In-core allocation").
template <class T>
multigrid::Plane<T> prefaulted_plane(int w, int h) {
  multigrid::Plane<T> p;
  p.width = w, p.height = h;
  const std::size_t n = static_cast<std::size_t>(w) * h;
  p.data.reserve(n);
  if (n * sizeof(T) >= util::kBigBuffer) util::populate(p.data.data(), n * sizeof(T));
  p.data.resize(n, T(0));
  return p;
}

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
  const auto t_rhs = Clock::now();
  // Each plane made once, in place (not copies of one), its pages mapped in one call.
  std::vector<Plane<T>> u, b, weights, diagonal;
  for (int c = 0; c < channels; ++c) u.push_back(prefaulted_plane<T>(w, h)), b.push_back(prefaulted_plane<T>(w, h));
  multigrid::InputRows<T> input(source, problem.hierarchy);
  {
    // The mean weights only where the mean is fixed by them (alpha == 0), else one row reused.
    const bool keep_weights = ops.singular;
    Plane<T> wt = prefaulted_plane<T>(w, keep_weights ? h : 1);
    Plane<T> d = prefaulted_plane<T>(source.has_weights() ? w : 0, source.has_weights() ? h : 0);
    std::vector<T> ur(n), br(n);
    for (int j = 0; j < h; ++j) {
      input.next(ur, br, {wt.row(keep_weights ? j : 0), static_cast<std::size_t>(w)},
                 {d.data.data() + static_cast<std::size_t>(j) * d.width, static_cast<std::size_t>(d.width)});
      for (int c = 0; c < channels; ++c) {
        std::copy_n(ur.begin() + static_cast<std::ptrdiff_t>(c) * w, w, u[c].row(j));
        std::copy_n(br.begin() + static_cast<std::ptrdiff_t>(c) * w, w, b[c].row(j));
      }
    }
    // The streamed schedule keeps the finest weights for later cycles as the policy says (0 or 1,
    // exact in half floats; rounded here all the same so that both read the same values).
    if (keep_weights) {
      if (half.rounds(0, "w") && cycles > 1) multigrid::round_to_half(wt.data.data(), wt.data.size());
      weights = multigrid::restrict_weights(ops, 0, std::move(wt));
    }
    if (source.has_weights()) diagonal = multigrid::restrict_weights(ops, 0, std::move(d));
  }
  summary.seconds_rhs = seconds_since(t_rhs);
  const multigrid::InputTotals totals = input.totals();
  summary.window_bytes = 2 * n * h * sizeof(T);

  const auto t_solve = Clock::now();
  ResidualLog log(channels, static_cast<bool>(opt.log));
  std::mutex progress_mutex;
  int cycles_done = 0;
  const auto report = [&] {
    if (!opt.progress) return;
    std::lock_guard<std::mutex> lock(progress_mutex);
    opt.progress(std::min(1.0, double(++cycles_done) / (double(channels) * cycles)));
  };
  const auto solve_channel = [&](int c, multigrid::InCoreVCycle<T>& vc) {
    log.set_rhs_norm(c, std::sqrt(totals.rhs_norms2[c]));
    log.initial(c, vc.residual_norm(u[c], b[c]));
    for (int k = 0; k < cycles; ++k) {
      multigrid::CycleProbe probe;
      vc.run(u[c], b[c], weights.empty() ? nullptr : &weights, &probe);
      log.cycle(c, vc.residual_norm(u[c], b[c]), probe);
      const double shift = mean_shift(ops.singular, totals.weighted_sums[c], totals.weight_total, probe.dots);
      if (shift != 0.0)
        for (T& v : u[c].data) v = static_cast<T>(static_cast<double>(v) + shift);
      // The streamed schedule carries the result to the next cycle in a store ("result").
      if (k + 1 < cycles && half.rounds("result")) multigrid::round_to_half(u[c].data.data(), u[c].data.size());
      report();
      if (log.settled(c, opt.tolerance)) break;
    }
  };
  const int threads = std::clamp(opt.threads, 1, std::max(channels, 1));
  const auto worker = [&](int t) {
    multigrid::InCoreVCycle<T> vc(ops, opt.sweeps, opt.coarse_tolerance);
    vc.set_sweeps(opt.sweeps, opt.post_sweeps);
    if (!diagonal.empty()) vc.set_diagonal(&diagonal);
    vc.set_half(&half);
    for (int c = t; c < channels; c += threads) solve_channel(c, vc);
  };
  run_workers(threads, worker);
  summary.seconds_solve = seconds_since(t_solve);
  log.finish(summary, opt);

  std::vector<float> row(n);
  for (int j = 0; j < h; ++j) {
    for (int c = 0; c < channels; ++c)
      std::transform(u[c].row(j), u[c].row(j) + w, row.begin() + static_cast<std::ptrdiff_t>(c) * w,
                     [](T v) { return static_cast<float>(v); });
    out.write_row(j, row);
  }
}

template void solve_incore<float>(GuidanceSource&, const SolverOptions&, RowWriter&, SolveSummary&);
template void solve_incore<double>(GuidanceSource&, const SolverOptions&, RowWriter&, SolveSummary&);

}  // namespace gdp::schedule
