// Band schedule throughput: Mpix/s for 1, 2, 4 bands (threads) against the streaming schedule.
#include <benchmark/benchmark.h>

#include <cmath>

#include "gdp/solver.h"

namespace gdp {
namespace {

// Gradients of a smooth RGB pattern, generated row by row (cheap next to the solve).
class Pattern final : public GuidanceSource {
 public:
  Pattern(int w, int h) : w_(w), h_(h) {}
  int width() const override { return w_; }
  int height() const override { return h_; }
  int channels() const override { return 3; }
  void read_row(int j, GuidanceRow& out) override {
    for (int c = 0; c < 3; ++c) {
      for (int i = 0; i + 1 < w_; ++i) out.gx[c * (w_ - 1) + i] = std::sin(0.01 * (i + c)) * 1e-2;
      for (int i = 0; i < w_; ++i) out.gy[c * w_ + i] = std::cos(0.02 * (j + c)) * 1e-2;
    }
  }

 private:
  int w_, h_;
};

class Discard final : public RowWriter {
 public:
  void write_row(int, std::span<const float> row) override { benchmark::DoNotOptimize(row.data()); }
};

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
