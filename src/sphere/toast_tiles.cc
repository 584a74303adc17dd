// WorldWideTelescope TOAST tile pyramids from TOAST PQ images (copies, rotations, 2x2 averages).
#include <fstream>

#include <fmt/format.h>

#include "gdp/errors.h"
#include "gdp/sphere.h"
#include "io/staged_directory.h"

namespace gdp::sphere {

namespace fs = std::filesystem;

namespace {

constexpr int kTile = 256;

Image halve(const Image& img) {
  Image out(img.width / 2, img.height / 2, img.channels);
  for (int c = 0; c < img.channels; ++c)
    for (int y = 0; y < out.height; ++y)
      for (int x = 0; x < out.width; ++x)
        out.at(c, x, y) = 0.25f * (img.at(c, 2 * x, 2 * y) + img.at(c, 2 * x + 1, 2 * y) +
                                   img.at(c, 2 * x, 2 * y + 1) + img.at(c, 2 * x + 1, 2 * y + 1));
  return out;
}

Image tile_of(const Image& square, int tx, int ty) {
  Image t(kTile, kTile, square.channels);
  for (int c = 0; c < square.channels; ++c)
    for (int y = 0; y < kTile; ++y)
      for (int x = 0; x < kTile; ++x) t.at(c, x, y) = square.at(c, tx * kTile + x, ty * kTile + y);
  return t;
}

void write_wtml(const fs::path& file, const std::string& name, int levels) {
  std::ofstream f(file);
  f << "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n"
    << "<Folder Name=\"" << name << "\" Group=\"Explorer\">\n"
    << "  <ImageSet Generic=\"False\" DataSetType=\"Sky\" BandPass=\"Visible\" Name=\"" << name << "\"\n"
    << "            Url=\"{1}/{3}/{3}_{2}.png\" BaseTileLevel=\"0\" TileLevels=\"" << levels << "\"\n"
    << "            BaseDegreesPerTile=\"180\" FileType=\".png\" BottomsUp=\"False\" Projection=\"Toast\"\n"
    << "            QuadTreeMap=\"\" CenterX=\"0\" CenterY=\"0\" OffsetX=\"0\" OffsetY=\"0\" Rotation=\"0\"\n"
    << "            Sparse=\"False\" ElevationModel=\"False\" StockSet=\"False\">\n"
    << "    <Credits>made by gdp sphere toast</Credits>\n"
    << "  </ImageSet>\n"
    << "</Folder>\n";
  if (!f.flush()) throw OutputError(file.string() + ": cannot write the WTML file");
}

}  // namespace

Image pq_to_square(const Image& pq) {
  const int h = pq.height, n = 2 * h;
  if (pq.width != 4 * h) throw UsageError("not a PQ image (width must be 4 x height)");
  Image sq(n, n, pq.channels);
  for (int c = 0; c < pq.channels; ++c)
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < 4 * h; ++i) {
        const auto [x, y] = pq_to_square_pixel(h, i, j);
        sq.at(c, x, y) = pq.at(c, i, j);
      }
  return sq;
}

void write_toast_pyramid(const Image& pq, const fs::path& dir, const ToastPyramidOptions& options) {
  int top = -1;
  for (int n = 0; n < 24; ++n)
    if (pq.height == (kTile / 2) << n) top = n;
  if (top < 0 || pq.width != 4 * pq.height)
    throw UsageError(fmt::format("{}x{} is not a TOAST PQ size (H = 128 * 2^n, W = 4H; make one with "
                                 "gdp sphere to-pq --height 128, 256, 512, ...)",
                                 pq.width, pq.height));
  const int deepest = options.levels < 0 ? top : options.levels;
  if (deepest > top)
    throw UsageError(fmt::format("--levels {} needs a PQ height of {} (this one, {}, reaches level {})", deepest,
                                 (kTile / 2) << deepest, pq.height, top));
  if (fs::exists(dir) && !(fs::is_directory(dir) && fs::is_empty(dir)))
    throw UsageError(dir.string() + ": exists and is not an empty directory");
  // Built next to the destination, renamed at the end: no partial pyramid is ever visible.
  io::write_staged_directory(dir, [&](const fs::path& temp) {
    Image square = pq_to_square(pq);
    for (int level = top; level > deepest; --level) square = halve(square);
    for (int level = deepest; level >= 0; --level) {
      const int tiles = 1 << level;
      for (int ty = 0; ty < tiles; ++ty) {
        fs::create_directories(temp / std::to_string(level) / std::to_string(ty));
        for (int tx = 0; tx < tiles; ++tx)
          write_image(temp / std::to_string(level) / std::to_string(ty) / fmt::format("{}_{}.png", ty, tx),
                      tile_of(square, tx, ty), options.write);
      }
      if (level > 0) square = halve(square);
    }
    write_wtml(temp / "toast.wtml", options.name, deepest);
  });
}

}  // namespace gdp::sphere
