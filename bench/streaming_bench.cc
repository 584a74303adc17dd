// Whole solves (right-hand side, one V-cycle, result rows) per schedule: streaming against in-core.
#include <benchmark/benchmark.h>

#include <cmath>

#include "gdp/solver.h"

namespace gdp {
namespace {

// Gradients of a smooth RGB pattern, generated row by row.
class Pattern final : public GuidanceSource {
 public:
  explicit Pattern(int n) : n_(n) {}
  int width() const override { return n_; }
  int height() const override { return n_; }
  int channels() const override { return 3; }
  void read_row(int j, GuidanceRow& out) override {
    for (int c = 0; c < 3; ++c) {
      for (int i = 0; i + 1 < n_; ++i) out.gx[c * (n_ - 1) + i] = std::sin(0.01 * (i + c)) * 1e-2;
      for (int i = 0; i < n_; ++i) out.gy[c * n_ + i] = std::cos(0.02 * (j + c)) * 1e-2;
    }
  }

 private:
  int n_;
};

class Discard final : public RowWriter {
 public:
  void write_row(int, std::span<const float> row) override { benchmark::DoNotOptimize(row.data()); }
};

// Arguments: image side, schedule (0 in-core, 1 streaming), threads.
void BM_Solve(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  SolverOptions o;
  o.schedule = state.range(1) ? Schedule::Streaming : Schedule::InCore;
  o.threads = static_cast<int>(state.range(2));
  for (auto _ : state) {
    Pattern source(n);
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
