// In-core V-cycle throughput and where its time goes (relaxation, residual+restriction, prolongation).
#include <benchmark/benchmark.h>

#include <random>

#include "gdp/solver.h"
#include "multigrid/incore_vcycle.h"
#include "multigrid/plane_ops.h"
#include "topology/topology.h"

namespace gdp::multigrid {
namespace {

struct Fixture {
  Hierarchy hierarchy;
  Operators<float> ops;
  Plane<float> u, b;
  Fixture(int w, int h)
      : hierarchy(build_hierarchy(*topology::make_topology(Domain::Planar), w, h, 0.0, 64)),
        ops(hierarchy), u(w, h), b(w, h) {
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> d(-1.0f, 1.0f);
    for (float& v : b.data) v = d(rng);
  }
};

// One V-cycle at k sweeps each way on `channels` planes; counter: megapixels per CPU second
// (per core; the wall time of a loaded machine says little).
void vcycles(benchmark::State& state, int side, int k) {
  const int channels = 3;
  Fixture f(side, side);
  InCoreVCycle<float> vc(f.ops, k, 1e-10);
  for (auto _ : state) {
    for (int c = 0; c < channels; ++c) vc.run(f.u, f.b);
    benchmark::DoNotOptimize(f.u.data.data());
  }
  state.counters["Mpix/s_RGB"] = benchmark::Counter(double(side) * side * state.iterations() / 1e6,
                                                    benchmark::Counter::kIsRate);
}

// At the default sweep count.
void BM_VCycle(benchmark::State& state) { vcycles(state, static_cast<int>(state.range(0)), SolverOptions{}.sweeps); }
BENCHMARK(BM_VCycle)->Arg(2048)->Arg(8192)->Unit(benchmark::kMillisecond)->Iterations(1);

// At k = 1 .. 5 sweeps (docs/multigrid.md, "The smoother's sweep count"): --benchmark_filter=BM_Sweeps.
void BM_Sweeps(benchmark::State& state) {
  vcycles(state, static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
}
BENCHMARK(BM_Sweeps)->ArgsProduct({{8192}, {1, 2, 3, 4, 5}})->Unit(benchmark::kMillisecond)->Iterations(1);

// One Gauss-Seidel sweep of the finest level (one channel).
void BM_RelaxSweep(benchmark::State& state) {
  Fixture f(2048, 2048);
  Scratch<float> s;
  const LevelOperator<float>& op = f.ops.levels[0];
  for (auto _ : state)
    for (int j = 0; j < op.height; ++j) relax(op, j, window(op, f.u, j), whole_row(op), f.u.row(j), f.b.row(j), s);
  state.counters["Mpix/s"] = benchmark::Counter(2048.0 * 2048 * state.iterations() / 1e6, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_RelaxSweep)->Unit(benchmark::kMillisecond)->UseRealTime();

// Residual and restriction of the finest level (one channel).
void BM_ResidualRestrict(benchmark::State& state) {
  Fixture f(2048, 2048);
  const LevelGeometry& g = f.hierarchy.levels[1];
  Plane<float> coarse(g.width(), g.height());
  Scratch<float> s;
  std::vector<float> r(2048);
  for (auto _ : state) {
    for (int j = 0; j < 2048; ++j) {
      residual(f.ops.levels[0], j, window(f.ops.levels[0], f.u, j), whole_row(f.ops.levels[0]), f.b.row(j), r.data(),
               s);
      const auto& py = g.py.rows[j];
      restrict_rows(g.px, py, r.data(), 0, whole_row(f.ops.levels[1]), coarse.row(py.index[0]), coarse.row(py.index[1]),
                    {0, 0}, s);
    }
  }
  state.counters["Mpix/s"] = benchmark::Counter(2048.0 * 2048 * state.iterations() / 1e6, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ResidualRestrict)->Unit(benchmark::kMillisecond)->UseRealTime();

// Prolongation into the finest level (one channel).
void BM_Prolong(benchmark::State& state) {
  Fixture f(2048, 2048);
  const LevelGeometry& g = f.hierarchy.levels[1];
  Plane<float> coarse(g.width(), g.height());
  Scratch<float> s;
  for (auto _ : state)
    for (int j = 0; j < 2048; ++j) {
      const auto& py = g.py.rows[j];
      prolong_rows(g.px, py, coarse.row(py.index[0]), coarse.row(py.index[1]), {0, 0}, true,
                   whole_row(f.ops.levels[0]), f.u.row(j), 0, s);
    }
  state.counters["Mpix/s"] = benchmark::Counter(2048.0 * 2048 * state.iterations() / 1e6, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Prolong)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace gdp::multigrid

BENCHMARK_MAIN();
