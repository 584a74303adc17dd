// Accuracy of one V-cycle against the converged solution on a real-photo stitching problem.
//
// Usage: stitch_accuracy IMAGE [SIZE=2048] [REGIONS=12] [SWEEPS=2,3,4,5,6,8]
// Crops a SIZE x SIZE square from IMAGE, splits it into REGIONS Voronoi cells with exposure
// offsets uniformly in +-40/255, and prints rms / max error (fraction of the value range) of
// one V-cycle for several sweep counts (each K or PRE/POST, as --iters) and both starting guesses.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <random>
#include <sstream>
#include <string>

#include "gdp/apps.h"
#include "gdp/image_io.h"

using namespace gdp;

int main(int argc, char** argv) try {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s IMAGE [SIZE] [REGIONS] [SWEEPS, e.g. 2,3,2/3]\n", argv[0]);
    return 2;
  }
  const int size = argc > 2 ? std::atoi(argv[2]) : 2048, regions = argc > 3 ? std::atoi(argv[3]) : 12;
  std::vector<std::string> counts;
  std::stringstream list(argc > 4 ? argv[4] : "2,3,4,5,6,8");
  for (std::string k; std::getline(list, k, ',');) {
    SolverOptions o;
    parse_sweeps(k, o);  // bad counts: one line, before the work
    counts.push_back(k);
  }
  const Image photo = read_image(argv[1]).image;
  const int n = std::min({size, photo.width, photo.height});
  std::mt19937 rng(2010);
  std::uniform_real_distribution<double> pos(0.0, n), off(-40.0 / 255, 40.0 / 255);
  std::vector<std::array<double, 2>> seeds(regions);
  std::vector<double> offsets(regions);
  for (int r = 0; r < regions; ++r) seeds[r] = {pos(rng), pos(rng)}, offsets[r] = off(rng);
  Image comp(n, n, photo.channels), labels(n, n, 1);
  float lo = 1e30f, hi = -1e30f;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      int best = 0;
      double bd = 1e300;
      for (int r = 0; r < regions; ++r) {
        const double d = std::hypot(x - seeds[r][0], y - seeds[r][1]);
        if (d < bd) bd = d, best = r;
      }
      labels.at(0, x, y) = static_cast<float>(best) / 255.0f;
      for (int c = 0; c < photo.channels; ++c) {
        const float v = photo.at(c, x, y) + static_cast<float>(offsets[best]);
        comp.at(c, x, y) = v;
        lo = std::min(lo, v), hi = std::max(hi, v);
      }
    }
  const double range = hi - lo;
  SolverOptions conv;
  conv.precision = Precision::Float64;
  conv.tolerance = 1e-10;
  const Image ref = stitch(comp, labels, {}, conv);
  std::printf("%dx%dx%d composite of %d regions, value range %.4f\n", n, n, comp.channels, regions, range);
  std::printf("%-6s %-10s %-12s %-12s %-10s\n", "sweeps", "start", "rms/range", "max/range", "seconds");
  for (bool from_composite : {true, false})
    for (const std::string& k : counts) {
      SolverOptions o;
      parse_sweeps(k, o);
      StitchOptions so;
      so.start_from_composite = from_composite;
      const auto t0 = std::chrono::steady_clock::now();
      const Image one = stitch(comp, labels, so, o);
      const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      double s = 0.0, m = 0.0;
      for (std::size_t i = 0; i < one.data.size(); ++i) {
        const double d = double(one.data[i]) - ref.data[i];
        s += d * d;
        m = std::max(m, std::abs(d));
      }
      std::printf("%-6s %-10s %-12.3e %-12.3e %-10.2f\n", k.c_str(), from_composite ? "composite" : "zero",
                  std::sqrt(s / one.data.size()) / range, m / range, sec);
    }
  return 0;
} catch (const std::exception& e) {  // a missing or unreadable IMAGE: one line naming it
  std::fprintf(stderr, "%s\n", e.what());
  return 2;
}
