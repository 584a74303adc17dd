// Generates a large stitching test case from a real photo: composite + label map, streamed.
//
// Usage: make_composite PHOTO WIDTH HEIGHT COMPOSITE_OUT LABELS_OUT [CELL=1024] [TRUTH_OUT]
// The photo is tiled with mirrored copies (no seams of its own) to WIDTH x HEIGHT and split
// into jittered-grid Voronoi regions about CELL pixels across, each with an exposure offset
// uniform in +-40/255. Rows are generated and written one at a time, so any size works; use
// .tif outputs (uncompressed) for gigapixel cases (PNG encoding is slow). TRUTH_OUT, when given,
// receives the tiled photo without the offsets: the held-out answer a stitch should approach.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <cstdlib>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "gdp/image_io.h"
#include "gdp/image_stream.h"

using namespace gdp;

int main(int argc, char** argv) try {
  if (argc < 6) {
    std::fprintf(stderr, "usage: %s PHOTO WIDTH HEIGHT COMPOSITE_OUT LABELS_OUT [CELL] [TRUTH_OUT]\n", argv[0]);
    return 2;
  }
  const Image photo = read_image(argv[1]).image;
  const int w = std::atoi(argv[2]), h = std::atoi(argv[3]), cell = argc > 6 ? std::atoi(argv[6]) : 1024;
  const int ch = std::min(photo.channels, 3);
  const int gx = (w + cell - 1) / cell + 2, gy = (h + cell - 1) / cell + 2;
  std::mt19937 rng(2010);
  std::uniform_real_distribution<double> jitter(0.0, 1.0), off(-40.0 / 255, 40.0 / 255);
  std::vector<double> sx(gx * gy), sy(gx * gy), offset(gx * gy);
  for (int k = 0; k < gx * gy; ++k) {
    sx[k] = ((k % gx) - 1 + jitter(rng)) * cell;
    sy[k] = ((k / gx) - 1 + jitter(rng)) * cell;
    offset[k] = off(rng);
  }
  const auto mirror = [](int v, int n) {
    const int p = v % (2 * n);
    return p < n ? p : 2 * n - 1 - p;
  };
  const auto options = [](const std::filesystem::path& path) {
    WriteOptions wo;
    wo.sample_type = SampleType::UInt8;
    const std::string ext = path.extension().string();
    if (ext == ".tif" || ext == ".tiff") wo.compression = "none";  // fast to write and read back; PNG refuses it
    return wo;
  };
  ImageFileWriter comp(argv[4], w, h, ch, options(argv[4])), labels(argv[5], w, h, 3, options(argv[5]));
  std::optional<ImageFileWriter> truth;
  if (argc > 7) truth.emplace(argv[7], w, h, ch, options(argv[7]));
  std::vector<float> crow(static_cast<std::size_t>(w) * ch), lrow(static_cast<std::size_t>(w) * 3), trow(crow.size());
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const int cx = x / cell + 1, cy = y / cell + 1;
      int best = 0;
      double bd = 1e300;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int k = (cy + dy) * gx + cx + dx;
          const double d = std::hypot(x - sx[k], y - sy[k]);
          if (d < bd) bd = d, best = k;
        }
      const int px = mirror(x, photo.width), py = mirror(y, photo.height);
      for (int c = 0; c < ch; ++c) {
        trow[static_cast<std::size_t>(c) * w + x] = photo.at(c, px, py);
        crow[static_cast<std::size_t>(c) * w + x] =
            std::clamp(photo.at(c, px, py) + static_cast<float>(offset[best]), 0.0f, 1.0f);
      }
      const int id = best + 1;
      for (int c = 0; c < 3; ++c) lrow[static_cast<std::size_t>(c) * w + x] = ((id >> (8 * c)) & 255) / 255.0f;
    }
    comp.write_row(y, crow);
    labels.write_row(y, lrow);
    if (truth) truth->write_row(y, trow);
  }
  comp.commit();
  labels.commit();
  if (truth) truth->commit();
  return 0;
} catch (const std::exception& e) {  // a missing or unreadable PHOTO: one line naming it
  std::fprintf(stderr, "%s\n", e.what());
  return 2;
}
