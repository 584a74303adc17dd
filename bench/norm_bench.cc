// The residual norm's parts per sample on 8192-wide float rows: residual, row_dot(r, r), row_squares(r), row_dot(w, u).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <random>

#include "multigrid/plane_ops.h"
#include "multigrid/row_kernels.h"
#include "topology/topology.h"
#include "util/seconds.h"

namespace gdp::multigrid {
namespace {

constexpr int kWidth = 8192, kRows = 64;

}  // namespace
}  // namespace gdp::multigrid

// Prints the minimum over `trials` (argument 1, default 15) of the CPU ns per sample of each part, the parts
// interleaved within every trial (load on the machine falls on all alike), and row_squares / row_dot(r, r).
int main(int argc, char** argv) {
  using namespace gdp::multigrid;
  const int trials = argc > 1 ? std::max(1, std::atoi(argv[1])) : 15;
  Hierarchy h = build_hierarchy(*gdp::topology::make_topology(gdp::Domain::Planar), kWidth, 4 * kRows, 0.0, 64);
  LevelOperator<float> op{h.levels[0], 0.0};
  Plane<float> u{kWidth, kRows}, b{kWidth, kRows}, r{kWidth, kRows}, w{kWidth, kRows};
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> d(-1.0f, 1.0f);
  for (Plane<float>* p : {&u, &b, &w})
    for (float& v : p->data) v = d(rng);
  Scratch<float> s;
  const char* names[] = {"residual", "row_dot(r, r)", "row_squares(r)", "row_dot(w, u)"};
  double best[4] = {1e30, 1e30, 1e30, 1e30}, sink = 0.0;
  for (int t = 0; t < trials; ++t)
    for (int k = 0; k < 4; ++k) {
      const double t0 = gdp::util::thread_cpu_seconds();
      for (int rep = 0; rep < 4; ++rep)
        for (int j = 2; j < kRows - 2; ++j) {
          if (k == 0) residual(op, j, window(op, u, j), whole_row(op), b.row(j), r.row(j), s);
          if (k == 1) sink += row_dot(r.row(j), r.row(j), kWidth);
          if (k == 2) sink += row_squares(r.row(j), kWidth);
          if (k == 3) sink += row_dot(w.row(j), u.row(j), kWidth);
        }
      best[k] = std::min(best[k], (gdp::util::thread_cpu_seconds() - t0) * 1e9 / (4.0 * (kRows - 4) * kWidth));
    }
  std::printf("CPU ns per sample, minimum of %d trials (checksum %g)\n", trials, sink);
  for (int k = 0; k < 4; ++k) std::printf("%-15s %7.3f\n", names[k], best[k]);
  std::printf("row_squares / row_dot(r, r): %.2fx\n", best[2] / best[1]);
  return 0;
}
