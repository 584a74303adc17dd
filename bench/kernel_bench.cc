// The window kernels per sample: on a whole row, a 72-column edge tile and a 4096-column interior lane.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <random>

#include "multigrid/plane_ops.h"
#include "multigrid/window_ops.h"
#include "topology/topology.h"

namespace gdp::multigrid {
namespace {

constexpr int kWidth = 8192, kRows = 64;

// An 8192-wide planar float level 0 (and level 1 for the transfers), random u and b.
struct Fixture {
  Hierarchy h = build_hierarchy(*topology::make_topology(Domain::Planar), kWidth, 4 * kRows, 0.0, 64);
  LevelOperator<float> op{h.levels[0], 0.0};
  Plane<float> u{kWidth, kRows}, b{kWidth, kRows}, r{kWidth, kRows}, coarse{kWidth / 2, kRows};
  Fixture() {
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> d(-1.0f, 1.0f);
    for (Plane<float>* p : {&u, &b, &coarse})
      for (float& v : p->data) v = d(rng);
  }
  static Fixture& get() {
    static Fixture f;
    return f;
  }
};

enum Kernel { kRelax, kResidual, kApply, kRestrict, kProlong };
const char* const kKernels[] = {"relax", "residual", "apply", "restrict", "prolong"};
const char* const kRanges[] = {"whole row", "edge tile [0,72)", "interior lane [2048,6144)"};
constexpr std::pair<int, int> kRangeColumns[] = {{0, kWidth}, {0, 72}, {2048, 6144}};

// One kernel over 60 interior rows (j = 2 .. 61), on the columns of range `range`.
void run(Kernel kernel, int range, Scratch<float>& s) {
  Fixture& f = Fixture::get();
  const LevelGeometry& g = f.h.levels[1];
  const auto [i0, i1] = kRangeColumns[range];
  const Columns cols = range == 0 ? whole_row(f.op) : Columns::range(kWidth, false, i0, i1);
  const Columns coarse = range == 0 ? Columns::whole(g.width(), false) : Columns::range(g.width(), false, i0 / 2, i1 / 2);
  for (int j = 2; j < 62; ++j) {
    const Window<float> w = window(f.op, f.u, j);
    const fem::ProlongationRow& py = g.py.rows[j];
    float* c0 = f.coarse.row(py.index[0] % kRows);
    float* c1 = f.coarse.row(py.index[1] % kRows);
    switch (kernel) {
      case kRelax: relax(f.op, j, w, cols, f.u.row(j), f.b.row(j), s); break;
      case kResidual: residual(f.op, j, w, cols, f.b.row(j), f.r.row(j), s); break;
      case kApply: apply(f.op, j, w, cols, f.r.row(j), s); break;
      case kRestrict: restrict_rows(g.px, py, f.r.row(j), 0, coarse, c0, c1, {0, 0}, s); break;
      case kProlong: prolong_rows(g.px, py, c0, c1, {0, 0}, true, cols, f.u.row(j), 0, s); break;
    }
  }
}

// Counter: nanoseconds per fine sample (the minimum of 9 repetitions is what to compare).
void BM_Kernel(benchmark::State& state) {
  const auto kernel = static_cast<Kernel>(state.range(0));
  const int range = static_cast<int>(state.range(1));
  Scratch<float> s;
  run(kernel, range, s);  // warm the scratch and the coefficient cache
  for (auto _ : state) {
    run(kernel, range, s);
    benchmark::ClobberMemory();
  }
  const auto [i0, i1] = kRangeColumns[range];
  state.SetLabel(std::string(kKernels[kernel]) + ", " + kRanges[range]);
  state.counters["ns/sample"] = benchmark::Counter(60.0 * (i1 - i0) * state.iterations() * 1e-9,
                                                   benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_Kernel)
    ->ArgsProduct({{kRelax, kResidual, kApply, kRestrict, kProlong}, {0, 1, 2}})
    ->Repetitions(9)
    ->ComputeStatistics("min", [](const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); })
    ->ReportAggregatesOnly(true);

}  // namespace
}  // namespace gdp::multigrid
BENCHMARK_MAIN();
