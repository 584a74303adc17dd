// The right-hand-side assembler (fem::RhsAssembler) alone: CPU ns per sample, and `check` hashes of its rows.
#include <time.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <vector>

#include "fem/rhs.h"

namespace gdp::fem {
namespace {

double cpu_seconds() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

// `rows` random guidance rows of a w-wide image (about a tenth of the edges cut, as a stitch's
// labels and masks would leave them).
std::vector<GuidanceRow> random_rows(int w, int rows, int channels, AxisBoundary bx, bool value, unsigned seed) {
  const int edges = bx == AxisBoundary::Periodic ? w : w - 1;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> dist(-1, 1);
  const auto fill = [&](std::vector<double>& v, std::size_t n) {
    v.resize(n);
    for (double& x : v) x = dist(rng) < -0.8 ? 0.0 : dist(rng);
  };
  std::vector<GuidanceRow> out(rows);
  for (GuidanceRow& r : out) {
    r.x_edges = edges;
    fill(r.gx, static_cast<std::size_t>(channels) * edges);
    fill(r.gy, static_cast<std::size_t>(channels) * w);
    fill(r.gy_above, static_cast<std::size_t>(channels) * w);
    if (value) fill(r.value, static_cast<std::size_t>(channels) * w);
  }
  return out;
}

void hash(std::uint64_t& h, const double* v, std::size_t n) {
  const auto* bytes = reinterpret_cast<const unsigned char*>(v);
  for (std::size_t i = 0; i < n * sizeof(double); ++i) h = (h ^ bytes[i]) * 1099511628211ull;
}

// Every row of a w x h image on each boundary kind, alpha 0 and 0.3, 1 and 3 channels, whole rows
// and (not Mirrored) the column windows [0, 9), [5, 40) and [w - 9, w): the hash of every b row.
std::uint64_t checksum(AxisBoundary bx, AxisBoundary by, int w, int h) {
  std::uint64_t hs = 1469598103934665603ull;
  const Axis x = make_fine_axis(w, bx), y = make_fine_axis(h, by);
  for (double alpha : {0.0, 0.3})
    for (int channels : {1, 3}) {
      const std::vector<GuidanceRow> rows = random_rows(w, h, channels, bx, alpha != 0.0, 11u + channels);
      std::vector<std::pair<int, int>> windows = {{0, w}};
      if (by != AxisBoundary::Mirrored) windows.insert(windows.end(), {{0, 9}, {5, 40}, {w - 9, w}});
      for (auto [begin, end] : windows) {
        RhsAssembler a(x, y, alpha, channels);
        if (begin != 0 || end != w) a.set_columns(begin, end);
        const auto sink = [&](int, int, std::span<const double> b) { hash(hs, b.data() + begin, end - begin); };
        for (int j = 0; j < h; ++j) a.push(j, rows[j], sink);
        a.finish(sink);
      }
    }
  return hs;
}

int print_checksums() {
  const AxisBoundary n = AxisBoundary::Neumann, p = AxisBoundary::Periodic, m = AxisBoundary::Mirrored;
  std::printf("checksum planar %016llx\n", static_cast<unsigned long long>(checksum(n, n, 61, 37)));
  std::printf("checksum cylindrical %016llx\n", static_cast<unsigned long long>(checksum(p, n, 61, 37)));
  std::printf("checksum pq %016llx\n", static_cast<unsigned long long>(checksum(p, m, 64, 32)));
  std::printf("checksum wide %016llx\n", static_cast<unsigned long long>(checksum(n, n, 1000, 9)));
  return 0;
}

}  // namespace
}  // namespace gdp::fem

// Prints the minimum over `trials` (argument 1, default 7) of the CPU ns per sample (per pixel and
// channel) to assemble an 8192-wide, 3-channel planar stitch's rows (alpha 0), 64 rows a trial.
// `check` instead prints bit-level hashes of the rows on every boundary kind, to compare builds.
int main(int argc, char** argv) {
  using namespace gdp::fem;
  if (argc > 1 && std::strcmp(argv[1], "check") == 0) return print_checksums();
  const int trials = argc > 1 ? std::max(1, std::atoi(argv[1])) : 7;
  constexpr int kWidth = 8192, kRows = 64, kChannels = 3, kHeight = 1 << 20;
  const Axis x = make_fine_axis(kWidth, AxisBoundary::Neumann), y = make_fine_axis(kHeight, AxisBoundary::Neumann);
  const std::vector<gdp::GuidanceRow> rows = random_rows(kWidth, 8, kChannels, AxisBoundary::Neumann, false, 5);
  double sum = 0.0, best = 1e30;
  const auto sink = [&](int, int, std::span<const double> b) { sum += b[kWidth / 2]; };
  RhsAssembler a(x, y, 0.0, kChannels);
  int j = 0;
  for (int t = 0; t < trials; ++t) {
    const double t0 = cpu_seconds();
    for (int k = 0; k < kRows; ++k, ++j) a.push(j, rows[j % rows.size()], sink);
    best = std::min(best, (cpu_seconds() - t0) * 1e9 / (double(kRows) * kWidth * kChannels));
  }
  std::printf("rhs assembly: %.3f CPU ns per sample (minimum of %d trials of %d rows; %g)\n", best, trials, kRows,
              sum);
  return 0;
}
