// Band schedule throughput: Mpix/s for 1, 2, 4 bands (threads) against the streaming schedule.
#include <benchmark/benchmark.h>

#include <cmath>

#include "bench_sources.h"
#include "gdp/solver.h"

namespace gdp {
namespace {

using bench::Discard;
using bench::Pattern;

// Arguments: width, height, bands (0: the streaming schedule, one lane).
void BM_Bands(benchmark::State& state) {
  const int w = static_cast<int>(state.range(0)), h = static_cast<int>(state.range(1));
  const int bands = static_cast<int>(state.range(2));
  SolverOptions o;
  o.schedule = bands ? Schedule::Bands : Schedule::Streaming;
  o.bands = std::max(bands, 1);
  o.threads = 1;
  double solve_seconds = 0.0;
  for (auto _ : state) {
    Pattern source(w, h);
    Discard out;
    SolveSummary s;
    solve(source, o, out, &s);
    solve_seconds += s.seconds_solve;
  }
  const double pixels = double(w) * h * state.iterations();
  state.counters["Mpix/s"] = benchmark::Counter(pixels / 1e6, benchmark::Counter::kIsRate);
  state.counters["Mpix/s_solve"] = pixels / 1e6 / solve_seconds;  // right-hand side assembly excluded
  state.counters["Mpix/s_per_band"] = pixels / 1e6 / solve_seconds / std::max(bands, 1);
}
// The paper's Table III sizes (8192x2048 .. 32768x8192); --benchmark_filter=width:8192/ for a quick run.
BENCHMARK(BM_Bands)
    ->ArgsProduct({{8192}, {2048}, {0, 1, 2, 4}})
    ->ArgsProduct({{16384}, {4096}, {0, 1, 2, 4}})
    ->ArgsProduct({{32768}, {8192}, {0, 1, 2, 4}})
    ->ArgNames({"width", "height", "bands"})
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->UseRealTime();

}  // namespace
}  // namespace gdp

BENCHMARK_MAIN();
