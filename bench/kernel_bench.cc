// The window kernels per sample on a whole row, a 72-column edge tile, a 4096-column interior lane and a
// 72-column interior tile, as ratios; then the half-float conversions of the row stores.
#include <algorithm>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <random>
#include <vector>

#include "multigrid/half_policy.h"
#include "multigrid/plane_ops.h"
#include "multigrid/window_ops.h"
#include "topology/topology.h"
#include "util/seconds.h"

namespace gdp::multigrid {
namespace {

constexpr int kWidth = 8192, kRows = 64, kFirst = 2, kLast = 62;

// An 8192-wide planar float level 0 (and level 1 for the transfers), random u and b; the rows'
// windows and transfer rows are looked up once, so the timings are the kernels' own.
struct Fixture {
  Hierarchy h = build_hierarchy(*topology::make_topology(Domain::Planar), kWidth, 4 * kRows, 0.0, 64);
  LevelOperator<float> op{h.levels[0], 0.0};
  Plane<float> u{kWidth, kRows}, b{kWidth, kRows}, r{kWidth, kRows}, diag{kWidth, kRows}, coarse{kWidth / 2, kRows};
  std::vector<Window<float>> windows;
  Fixture() {
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> d(-1.0f, 1.0f);
    for (Plane<float>* p : {&u, &b, &coarse})
      for (float& v : p->data) v = d(rng);
    for (float& v : diag.data) v = 0.5f + d(rng) / 4;  // relaxd: with a per-pixel diagonal term
    for (int j = 0; j < kRows; ++j) windows.push_back(window(op, u, j));
  }
};

enum Kernel { kRelax, kResidual, kApply, kRestrict, kProlong, kRelaxDiag, kKernelCount };
const char* const kKernels[] = {"relax", "residual", "apply", "restrict", "prolong", "relaxd"};
constexpr std::pair<int, int> kRangeColumns[] = {{0, kWidth}, {0, 72}, {2048, 6144}, {2048, 2120}};
constexpr int kRanges = 4;

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
      case kRelaxDiag: relax(f.op, j, w, cols, f.u.row(j), f.b.row(j), s, f.diag.row(j)); break;
      case kKernelCount: break;
    }
  }
}

// CPU ns per fine sample of one kernel on one range, over about 2M samples.
double measure(Fixture& f, Kernel kernel, int range, Scratch<float>& s) {
  const auto [i0, i1] = kRangeColumns[range];
  const long samples = long(kLast - kFirst) * (i1 - i0);
  const int reps = int(std::max(1L, 2000000 / samples));
  const double t0 = gdp::util::thread_cpu_seconds();
  for (int k = 0; k < reps; ++k) run(f, kernel, range, s);
  return (gdp::util::thread_cpu_seconds() - t0) * 1e9 / (double(reps) * double(samples));
}

// FNV-1a over the bytes of a plane: the kernels' results bit for bit.
template <class T>
void hash(std::uint64_t& h, const Plane<T>& p) {
  const auto* bytes = reinterpret_cast<const unsigned char*>(p.data.data());
  for (size_t i = 0; i < p.data.size() * sizeof(T); ++i) h = (h ^ bytes[i]) * 1099511628211ull;
}

// Every kernel on every row of a 512x128 level of `domain`: whole rows, planar ranges [0, 72) and
// [100, 301) forward and backward, with and without a per-pixel diagonal; the hash of all results.
template <class T>
std::uint64_t checksum(Domain domain) {
  const int w = 512, h = 128;
  Hierarchy hy = build_hierarchy(*topology::make_topology(domain), w, h, 0.0, 16);
  LevelOperator<T> op{hy.levels[0], 0.0};
  const LevelGeometry& g = hy.levels[1];
  Plane<T> u{w, h}, b{w, h}, r{w, h}, d{w, h}, coarse{g.width(), g.height()};
  std::mt19937 rng(7);
  std::uniform_real_distribution<T> dist(-1, 1);
  for (Plane<T>* p : {&u, &b, &coarse}) for (T& v : p->data) v = dist(rng);
  for (T& v : d.data) v = T(0.5) + dist(rng) / 4;
  Scratch<T> s;
  std::uint64_t hs = 1469598103934665603ull;
  std::vector<Columns> ranges = {whole_row(op)};
  if (domain == Domain::Planar)
    for (bool fwd : {true, false}) for (auto [i0, i1] : {std::pair{0, 72}, std::pair{100, 301}, std::pair{440, 512}})
      ranges.push_back(Columns::range(w, false, i0, i1, fwd));
  for (const Columns& cols : ranges)
    for (const T* diag : {static_cast<const T*>(nullptr), static_cast<const T*>(d.data.data())})
      for (int j = 0; j < h; ++j) {
        const T* dj = diag ? d.row(j) : nullptr;
        relax(op, j, window(op, u, j), cols, u.row(j), b.row(j), s, dj);
        residual(op, j, window(op, u, j), cols, b.row(j), r.row(j), s, dj);
        apply(op, j, window(op, u, j), cols, b.row(j), s, dj);
      }
  for (int j = 0; j < h; ++j) {
    const fem::ProlongationRow& py = g.py.rows[j];
    restrict_rows(g.px, py, r.row(j), 0, Columns::whole(g.width(), op.periodic_x), coarse.row(py.index[0]),
                  coarse.row(py.index[1]), {0, 0}, s);
    prolong_rows(g.px, py, coarse.row(py.index[0]), coarse.row(py.index[1]), {0, 0}, true, whole_row(op), u.row(j), 0, s);
  }
  for (const Plane<T>* p : {&u, &b, &r, &coarse}) hash(hs, *p);
  return hs;
}

// CPU ns per sample of the row stores' half-float conversions (to_half, from_half) on the fixture's u,
// the minimum over `trials` (run against another build's libgdp through LD_LIBRARY_PATH to compare).
void print_half_conversions(Fixture& f, int trials) {
  std::vector<_Float16> half(f.u.data.size());
  std::vector<float> back(f.u.data.size());
  double best[2] = {1e30, 1e30};
  for (int t = 0; t < trials; ++t) {
    double t0 = gdp::util::thread_cpu_seconds();
    for (int k = 0; k < 4; ++k) to_half(f.u.data.data(), half.data(), half.size());
    best[0] = std::min(best[0], (gdp::util::thread_cpu_seconds() - t0) * 1e9 / (4.0 * double(half.size())));
    t0 = gdp::util::thread_cpu_seconds();
    for (int k = 0; k < 4; ++k) from_half(half.data(), back.data(), back.size());
    best[1] = std::min(best[1], (gdp::util::thread_cpu_seconds() - t0) * 1e9 / (4.0 * double(back.size())));
  }
  std::printf("half floats: to_half %.3f, from_half %.3f CPU ns per sample\n", best[0], best[1]);
}

// `kernel_bench check`: one hash per domain and precision, to compare builds bit for bit.
int print_checksums() {
  for (Domain domain : {Domain::Planar, Domain::Cylindrical, Domain::Spherical})
    std::printf("checksum domain %d: float %016llx double %016llx\n", int(domain),
                static_cast<unsigned long long>(checksum<float>(domain)),
                static_cast<unsigned long long>(checksum<double>(domain)));
  return 0;
}

}  // namespace
}  // namespace gdp::multigrid

// Prints, per kernel, the minimum over `trials` (argument 1, default 15) of the ns per sample on each range
// (the ranges interleaved within every trial, so load on the machine falls on all three alike) and the ratios.
// `check` instead prints bit-level checksums of every kernel. Argument 2, a range (0 whole row, 1 edge
// tile, 2 interior lane, 3 interior tile), runs only that one, and argument 3, a kernel's name, only that kernel
// (for a profiler).
int main(int argc, char** argv) {
  using namespace gdp::multigrid;
  if (argc > 1 && std::strcmp(argv[1], "check") == 0) return print_checksums();
  const int trials = argc > 1 ? std::max(1, std::atoi(argv[1])) : 15;
  const int only = argc > 2 ? std::atoi(argv[2]) : -1;
  const char* kernel_only = argc > 3 ? argv[3] : nullptr;
  Fixture f;
  Scratch<float> s;
  std::printf("CPU ns per sample, minimum of %d trials; ratios of those minima\n", trials);
  std::printf("%-9s %9s %9s %9s %9s %11s %11s %11s %11s\n", "kernel", "row", "edge", "interior", "tile", "edge/row",
              "lane/row", "tile/row", "edge/tile");
  double total = 0.0;
  for (int k = 0; k < kKernelCount; ++k) {
    const auto kernel = static_cast<Kernel>(k);
    if (kernel_only && std::strcmp(kernel_only, kKernels[k]) != 0) continue;
    double best[kRanges] = {1e30, 1e30, 1e30, 1e30};
    const double t0 = gdp::util::thread_cpu_seconds();
    for (int r = 0; r < kRanges; ++r) run(f, kernel, r, s);  // warm the scratch and the coefficient cache
    for (int t = 0; t < trials; ++t)
      for (int r = 0; r < kRanges; ++r)
        if (only < 0 || r == only) best[r] = std::min(best[r], measure(f, kernel, r, s));
    total += gdp::util::thread_cpu_seconds() - t0;
    std::printf("%-9s %9.3f %9.3f %9.3f %9.3f %10.2fx %10.2fx %10.2fx %10.2fx\n", kKernels[k], best[0], best[1], best[2],
                best[3], best[1] / best[0], best[2] / best[0], best[3] / best[0], best[1] / best[3]);
  }
  std::printf("CPU seconds in all: %.2f\n", total);
  if (!kernel_only) print_half_conversions(f, trials);
  return 0;
}
