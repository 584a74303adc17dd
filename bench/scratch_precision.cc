// Which scratch quantities can be half floats: one V-cycle's error with each stored as half.
//
// Usage: scratch_precision COMPOSITE LABELS
// (bench/make_composite makes both; bench/scratch_bench.sh runs this on a 2048² crop.) Solves the
// stitch to convergence in double precision, then runs one and two V-cycles (streaming, float)
// with float scratch, with each quantity as 16-bit floats and with --half-scratch, and prints the rms and max error
// against the converged answer and against the float-scratch result (fractions of the value
// range), with the scratch bytes per pixel.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "gdp/apps.h"
#include "gdp/image_io.h"

using namespace gdp;

namespace {

struct Error {
  double rms = 0.0, max = 0.0;
};

Error difference(const Image& a, const Image& b, double range) {
  Error e;
  for (std::size_t i = 0; i < a.data.size(); ++i) {
    const double d = double(a.data[i]) - b.data[i];
    e.rms += d * d;
    e.max = std::max(e.max, std::abs(d));
  }
  e.rms = std::sqrt(e.rms / a.data.size()) / range;
  e.max /= range;
  return e;
}

}  // namespace

int main(int argc, char** argv) try {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s COMPOSITE LABELS\n", argv[0]);
    return 2;
  }
  const Image comp = read_image(argv[1]).image, labels = read_image(argv[2]).image;
  const auto [lo, hi] = std::minmax_element(comp.data.begin(), comp.data.end());
  const double range = *hi - *lo, pixels = double(comp.width) * comp.height;
  SolverOptions conv;
  conv.precision = Precision::Float64;
  conv.tolerance = 1e-10;
  const Image truth = stitch(comp, labels, {}, conv);
  std::printf("%dx%dx%d composite, value range %.4f\n", comp.width, comp.height, comp.channels, range);
  std::printf("%-7s %-22s %-11s %-11s %-11s %-11s %-8s\n", "cycles", "half quantities", "rms/range", "max/range",
              "rms vs flt", "max vs flt", "B/pixel");
  const std::vector<std::vector<std::string>> sets = {
      {}, {"level0-u"}, {"u"}, {"level0-b"}, {"b"}, {"u", "b"}, {"w"}, {"result"}, {"u", "b", "w", "result"}};
  for (int cycles : {1, 2}) {
    Image exact;
    const auto run = [&](const std::string& name, SolverOptions o) {
      o.vcycles = cycles;
      SolveSummary s;
      const Image out = stitch(comp, labels, {}, o, &s);
      if (exact.data.empty()) exact = out;
      const Error e = difference(out, truth, range), f = difference(out, exact, range);
      std::printf("%-7d %-22s %-11.3e %-11.3e %-11.3e %-11.3e %-8.2f\n", cycles, name.c_str(), e.rms, e.max, f.rms,
                  f.max, s.scratch_bytes / pixels);
    };
    for (const auto& half : sets) {
      SolverOptions o;
      o.half_quantities = half;
      std::string name;
      for (const std::string& q : half) name += (name.empty() ? "" : "+") + q;
      run(half.empty() ? "(none)" : name, o);
    }
    SolverOptions o;
    o.scratch = ScratchPrecision::Narrow;
    run("--half-scratch", o);
  }
  return 0;
} catch (const std::exception& e) {  // a missing or unreadable file: one line naming it
  std::fprintf(stderr, "%s\n", e.what());
  return 2;
}
