// The window kernels per sample on a whole row, a 72-column edge tile and a 4096-column interior lane, as ratios.
#include <time.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "multigrid/plane_ops.h"
#include "multigrid/window_ops.h"
#include "topology/topology.h"

namespace gdp::multigrid {
namespace {

constexpr int kWidth = 8192, kRows = 64, kFirst = 2, kLast = 62;

// An 8192-wide planar float level 0 (and level 1 for the transfers), random u and b; the rows'
// windows and transfer rows are looked up once, so the timings are the kernels' own.
struct Fixture {
  Hierarchy h = build_hierarchy(*topology::make_topology(Domain::Planar), kWidth, 4 * kRows, 0.0, 64);
  LevelOperator<float> op{h.levels[0], 0.0};
  Plane<float> u{kWidth, kRows}, b{kWidth, kRows}, r{kWidth, kRows}, coarse{kWidth / 2, kRows};
  std::vector<Window<float>> windows;
  Fixture() {
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> d(-1.0f, 1.0f);
    for (Plane<float>* p : {&u, &b, &coarse})
      for (float& v : p->data) v = d(rng);
    for (int j = 0; j < kRows; ++j) windows.push_back(window(op, u, j));
  }
};

enum Kernel { kRelax, kResidual, kApply, kRestrict, kProlong };
const char* const kKernels[] = {"relax", "residual", "apply", "restrict", "prolong"};
constexpr std::pair<int, int> kRangeColumns[] = {{0, kWidth}, {0, 72}, {2048, 6144}};

// One kernel over 60 interior rows, on the columns of range `range`.
void run(Fixture& f, Kernel kernel, int range, Scratch<float>& s) {
  const LevelGeometry& g = f.h.levels[1];
  const auto [i0, i1] = kRangeColumns[range];
  const Columns cols = range == 0 ? whole_row(f.op) : Columns::range(kWidth, false, i0, i1);
  const Columns coarse = range == 0 ? Columns::whole(g.width(), false) : Columns::range(g.width(), false, i0 / 2, i1 / 2);
  for (int j = kFirst; j < kLast; ++j) {
    const Window<float>& w = f.windows[j];
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

double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

// CPU ns per fine sample of one kernel on one range, over about 2M samples.
double measure(Fixture& f, Kernel kernel, int range, Scratch<float>& s) {
  const auto [i0, i1] = kRangeColumns[range];
  const long samples = long(kLast - kFirst) * (i1 - i0);
  const int reps = int(std::max(1L, 2000000 / samples));
  const double t0 = cpu_seconds();
  for (int k = 0; k < reps; ++k) run(f, kernel, range, s);
  return (cpu_seconds() - t0) * 1e9 / (double(reps) * double(samples));
}

}  // namespace
}  // namespace gdp::multigrid

// Prints, per kernel, the minimum over `trials` (argument 1, default 15) of the ns per sample on each range
// (the ranges interleaved within every trial, so load on the machine falls on all three alike) and the ratios.
// Argument 2, a range (0 whole row, 1 edge tile, 2 interior lane), runs only that one (for a profiler).
int main(int argc, char** argv) {
  using namespace gdp::multigrid;
  const int trials = argc > 1 ? std::max(1, std::atoi(argv[1])) : 15;
  const int only = argc > 2 ? std::atoi(argv[2]) : -1;
  Fixture f;
  Scratch<float> s;
  std::printf("CPU ns per sample, minimum of %d trials; ratios of those minima\n", trials);
  std::printf("%-9s %9s %9s %9s %11s %11s %11s\n", "kernel", "row", "edge", "interior", "edge/row", "lane/row",
              "edge/lane");
  double total = 0.0;
  for (int k = 0; k < 5; ++k) {
    const auto kernel = static_cast<Kernel>(k);
    double best[3] = {1e30, 1e30, 1e30};
    const double t0 = cpu_seconds();
    for (int r = 0; r < 3; ++r) run(f, kernel, r, s);  // warm the scratch and the coefficient cache
    for (int t = 0; t < trials; ++t)
      for (int r = 0; r < 3; ++r)
        if (only < 0 || r == only) best[r] = std::min(best[r], measure(f, kernel, r, s));
    total += cpu_seconds() - t0;
    std::printf("%-9s %9.3f %9.3f %9.3f %10.2fx %10.2fx %10.2fx\n", kKernels[k], best[0], best[1], best[2],
                best[1] / best[0], best[2] / best[0], best[1] / best[2]);
  }
  std::printf("CPU seconds in all: %.2f\n", total);
  return 0;
}
