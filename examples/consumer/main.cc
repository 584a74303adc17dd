// Example consumer of the gdp library: stitches two exposures of a ramp in memory and checks
// that the seam between them is gone; with a file name, also writes the result there.
#include <cmath>
#include <cstdio>

#include "gdp/apps.h"
#include "gdp/errors.h"
#include "gdp/image_io.h"

int main(int argc, char** argv) {
  // An RGB ramp whose right half was taken 0.2 brighter: label 0 on the left, 0.5 on the right.
  const int width = 64, height = 32, seam = width / 2;
  gdp::Image composite(width, height, 3), labels(width, height, 1);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const bool right = x >= seam;
      for (int c = 0; c < 3; ++c) composite.at(c, x, y) = 0.1f * (c + 1) + 0.004f * x + (right ? 0.2f : 0.0f);
      labels.at(0, x, y) = right ? 0.5f : 0.0f;
    }
  }
  gdp::SolverOptions solver;
  solver.tolerance = 1e-6;  // V-cycles until the relative residual is below this
  try {
    const gdp::Image result = gdp::stitch(composite, labels, gdp::StitchOptions{}, solver);
    // Stitching keeps the gradients inside each half and sets those across the seam to zero.
    double worst = 0.0;
    for (int c = 0; c < 3; ++c) {
      for (int y = 0; y < height; ++y) {
        worst = std::fmax(worst, std::fabs(result.at(c, seam, y) - result.at(c, seam - 1, y)));
      }
    }
    const double before = composite.at(0, seam, 0) - composite.at(0, seam - 1, 0);
    std::printf("step across the seam: %.4f before stitching, %.6f after\n", before, worst);
    if (argc > 1) gdp::write_image(argv[1], result, gdp::WriteOptions{});
    if (worst > 1e-3) {
      std::printf("FAILED: the seam is still there\n");
      return 1;
    }
  } catch (const gdp::Error& e) {
    std::fprintf(stderr, "gdp_consumer: %s\n", e.what());
    return 2;
  }
  std::printf("ok\n");
  return 0;
}
