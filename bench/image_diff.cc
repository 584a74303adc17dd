// Streams two images row by row and prints their largest difference as a fraction of the first's value range.
//
// Usage: image_diff REFERENCE OTHER
// Prints one line of JSON: {"max_abs": ..., "rms": ..., "range": ..., "max_rel": max_abs / range}
// (range: the reference's largest minus smallest sample over all channels). Memory is a few rows
// whatever the size, so gigapixel outputs compare in constant memory. Exit 2 (one line naming the
// files) when a file cannot be read or the sizes or channel counts differ.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <vector>

#include "gdp/image_stream.h"

using namespace gdp;

int main(int argc, char** argv) try {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s REFERENCE OTHER\n", argv[0]);
    return 2;
  }
  ImageFileReader a(argv[1]), b(argv[2]);
  if (a.width() != b.width() || a.height() != b.height() || a.channels() != b.channels()) {
    std::fprintf(stderr, "image_diff: %s is %dx%dx%d but %s is %dx%dx%d\n", argv[1], a.width(), a.height(),
                 a.channels(), argv[2], b.width(), b.height(), b.channels());
    return 2;
  }
  std::vector<float> ra(static_cast<std::size_t>(a.width()) * a.channels()), rb(ra.size());
  double max_abs = 0, sum_sq = 0, lo = INFINITY, hi = -INFINITY;
  for (int y = 0; y < a.height(); ++y) {
    a.read_row(y, ra);
    b.read_row(y, rb);
    for (std::size_t i = 0; i < ra.size(); ++i) {
      const double d = std::abs(static_cast<double>(ra[i]) - rb[i]);
      max_abs = std::max(max_abs, d);
      sum_sq += d * d;
      lo = std::min(lo, static_cast<double>(ra[i]));
      hi = std::max(hi, static_cast<double>(ra[i]));
    }
  }
  const double range = hi > lo ? hi - lo : 1.0;
  const double rms = std::sqrt(sum_sq / (static_cast<double>(ra.size()) * a.height()));
  std::printf("{\"max_abs\": %.6g, \"rms\": %.6g, \"range\": %.6g, \"max_rel\": %.6g}\n", max_abs, rms, range,
              max_abs / range);
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "image_diff: %s\n", e.what());
  return 2;
}
