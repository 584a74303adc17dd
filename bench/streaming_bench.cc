// Whole solves (right-hand side, one V-cycle, result rows) per schedule: streaming against in-core.
#include <benchmark/benchmark.h>

#include <cmath>

#include "bench_sources.h"
#include "gdp/solver.h"

namespace gdp {
namespace {

using bench::Discard;
using bench::Pattern;

// Arguments: image side, schedule (0 in-core, 1 streaming), threads.
void BM_Solve(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  SolverOptions o;
  o.schedule = state.range(1) ? Schedule::Streaming : Schedule::InCore;
  o.threads = static_cast<int>(state.range(2));
  for (auto _ : state) {
    Pattern source(n, n);
    Discard out;
    solve(source, o, out);
  }
  state.counters["Mpix/s_RGB"] = benchmark::Counter(double(n) * n * state.iterations() / 1e6, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Solve)
    ->ArgsProduct({{2048, 4096}, {0, 1}, {1}})
    ->Args({4096, 1, 5})
    ->ArgNames({"side", "streaming", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(2);

}  // namespace
}  // namespace gdp

BENCHMARK_MAIN();
