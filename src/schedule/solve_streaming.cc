// The streaming solve schedule: V-cycles as pairs of passes over the rows (default).
#include <algorithm>
#include <cmath>

#include "schedule/input_rows.h"
#include "schedule/solve_parts.h"
#include "schedule/streaming_vcycle.h"

namespace gdp::schedule {
namespace {

// The first level (>= 1) whose planes, u and b for every channel, fit in `bytes`.
template <class T>
int first_incore_level(const multigrid::Operators<T>& ops, int channels, std::size_t bytes) {
  for (int l = 1; l < ops.count(); ++l) {
    const auto& op = ops.levels[l];
    if (2.0 * channels * op.width * static_cast<double>(op.height) * sizeof(T) <= static_cast<double>(bytes)) return l;
  }
  return ops.count() - 1;
}

}  // namespace

template <class T>
void solve_streaming(GuidanceSource& source, const SolverOptions& opt, RowWriter& out, SolveSummary& summary) {
  const Problem<T> problem(source, opt, summary);
  const multigrid::Operators<T>& ops = problem.ops;
  if (ops.count() == 1) return solve_incore<T>(source, opt, out, summary);  // nothing to stream
  const int w = source.width(), h = source.height(), channels = source.channels();
  const std::size_t n = static_cast<std::size_t>(channels) * w;
  const auto t_start = Clock::now();

  typename StreamingVCycle<T>::Settings settings;
  settings.channels = channels;
  settings.sweeps = opt.sweeps;
  settings.coarse_tolerance = opt.coarse_tolerance;
  settings.incore_from = first_incore_level(ops, channels, opt.incore_bytes);
  settings.measure_initial = settings.measure_final = true;
  settings.weights = ops.singular;
  settings.more_cycles = (opt.tolerance > 0.0 ? opt.max_vcycles : opt.vcycles) > 1;
  settings.stores.dir = opt.temp_dir;
  settings.stores.encoding = opt.half_scratch ? StoreEncoding::Half : StoreEncoding::Native;
  StreamingVCycle<T> vcycle(ops, settings);
  InputRows<T> input(source, problem.hierarchy);
  summary.schedule = "streaming";
  summary.streamed_levels = settings.incore_from;

  const int cycles = opt.tolerance > 0.0 ? opt.max_vcycles : opt.vcycles;
  // The result of one V-cycle, kept for the next one (and, when iterating to a tolerance,
  // until it is known to be the last).
  std::unique_ptr<RowStore<T>> carry;
  if (cycles > 1) carry = std::make_unique<RowStore<T>>(settings.stores, n, h, "result");
  std::vector<T> u(n), b(n), wt(w);
  std::vector<float> row(n);
  std::vector<double> shift(channels, 0.0);
  ResidualLog log(channels, static_cast<bool>(opt.log));
  double seconds_input = 0.0;
  const auto emit = [&](int j) {
    std::transform(u.begin(), u.end(), row.begin(), [](T v) { return static_cast<float>(v); });
    out.write_row(j, row);
  };
  const auto report = [&](int k, int pass, int j) {
    if (opt.progress && (j % 64 == 63 || j + 1 == h))
      opt.progress((2.0 * k + pass + double(j + 1) / h) / (2.0 * cycles));
  };

  for (int k = 0; k < cycles; ++k) {
    vcycle.begin_cycle();
    if (carry) carry->rewind();
    for (int j = 0; j < h; ++j) {
      if (k == 0) {
        const auto t = Clock::now();
        input.next(u, b, wt);
        seconds_input += seconds_since(t);
        vcycle.push(u, b, wt);
      } else {
        carry->read(u);
        vcycle.push(u, {}, {});
      }
      report(k, 0, j);
    }
    for (int c = 0; c < channels; ++c) {
      if (k == 0) {
        log.set_rhs_norm(c, std::sqrt(input.rhs_norms2()[c]));
        log.initial(c, vcycle.initial_norm(c));
      }
      shift[c] = mean_shift(ops.singular, input.weighted_sums()[c], input.weight_total(), vcycle.probe(c).dots);
    }
    const bool surely_last = k + 1 == cycles;
    if (carry && !surely_last) carry->clear();
    for (int j = 0; j < h; ++j) {
      vcycle.pull(u);
      for (int c = 0; c < channels; ++c) {
        if (shift[c] == 0.0) continue;
        T* p = u.data() + static_cast<std::size_t>(c) * w;
        for (int i = 0; i < w; ++i) p[i] = static_cast<T>(static_cast<double>(p[i]) + shift[c]);
      }
      if (surely_last) emit(j);
      else carry->append(u);
      report(k, 1, j);
    }
    summary.scratch_bytes = std::max(summary.scratch_bytes, vcycle.store_bytes() + (carry ? carry->bytes() : 0));
    bool converged = opt.tolerance > 0.0;
    for (int c = 0; c < channels; ++c) {
      log.cycle(c, vcycle.final_norm(c), vcycle.probe(c));
      converged = converged && log.last(c) <= opt.tolerance;
    }
    if (surely_last) break;
    if (converged) {  // the carried result is the answer
      carry->rewind();
      for (int j = 0; j < h; ++j) {
        carry->read(u);
        emit(j);
      }
      break;
    }
  }
  summary.window_bytes = vcycle.window_bytes();
  summary.seconds_rhs = seconds_input;
  summary.seconds_solve = seconds_since(t_start) - seconds_input;
  log.finish(summary, opt);
}

template void solve_streaming<float>(GuidanceSource&, const SolverOptions&, RowWriter&, SolveSummary&);
template void solve_streaming<double>(GuidanceSource&, const SolverOptions&, RowWriter&, SolveSummary&);

}  // namespace gdp::schedule
