// WorldWideTelescope TOAST tile pyramids from TOAST PQ images (copies, rotations, 2x2 averages).
#include <algorithm>
#include <fstream>
#include <vector>

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

[[noreturn]] void throw_not_toast(int width, int height) {
  throw UsageError(fmt::format("{}x{} is not a TOAST PQ size (H = 128 * 2^n, W = 4H; make one with "
                               "gdp sphere to-pq --height 128, 256, 512, ...)",
                               width, height));
}

// The levels 0 .. deepest of a pyramid, each a strip of 256 square rows filled top to bottom: a
// full strip's tiles are written, and its 2x2 average (128 rows) goes into the level above.
class StripPyramid {
 public:
  StripPyramid(const fs::path& root, int deepest, int channels, const WriteOptions& write)
      : root_(root), write_(write), filled_(deepest + 1, 0), index_(deepest + 1, 0) {
    for (int level = 0; level <= deepest; ++level) strips_.emplace_back(kTile << level, kTile, channels);
  }

  // Rows of level `level` (its full width), the next ones of its strip.
  void add(int level, const Image& rows) {
    Image& strip = strips_[level];
    for (int c = 0; c < strip.channels; ++c)
      std::copy_n(rows.row(c, 0).data(), rows.plane_size(), &strip.at(c, 0, filled_[level]));
    filled_[level] += rows.height;
    if (filled_[level] < kTile) return;
    const fs::path folder = root_ / std::to_string(level) / std::to_string(index_[level]);
    fs::create_directories(folder);
    for (int tx = 0; tx < 1 << level; ++tx)
      write_image(folder / fmt::format("{}_{}.png", index_[level], tx), tile_of(strip, tx, 0), write_);
    filled_[level] = 0;
    ++index_[level];
    if (level > 0) add(level - 1, halve(strip));
  }

 private:
  fs::path root_;
  WriteOptions write_;
  std::vector<Image> strips_;
  std::vector<int> filled_, index_;
};

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

int square_row_source(int height, int y) { return y >= height ? y - height : height - 1 - y; }

void square_row_from_pq(int height, int y, std::span<const float> pq_row, std::span<float> out) {
  const int n = 2 * height;
  if (y >= height) {
    std::copy(pq_row.begin(), pq_row.begin() + n, out.begin());
    return;
  }
  for (int x = 0; x < n; ++x) out[x] = pq_row[4 * height - 1 - x];
}

void write_toast_pyramid(const Image& pq, const fs::path& dir, const ToastPyramidOptions& options) {
  if (pq.width != 4 * pq.height) throw_not_toast(pq.width, pq.height);
  const int n = 2 * pq.height;
  write_toast_pyramid(
      pq.height, pq.channels,
      [&](int y, std::span<float> row) {
        const int j = square_row_source(pq.height, y);
        for (int c = 0; c < pq.channels; ++c)
          square_row_from_pq(pq.height, y, pq.row(c, j), row.subspan(static_cast<std::size_t>(c) * n, n));
      },
      dir, options);
}

void write_toast_pyramid(int height, int channels, const ToastSquareRows& rows, const fs::path& dir,
                         const ToastPyramidOptions& options) {
  int top = -1;
  for (int n = 0; n < 24; ++n)
    if (height == (kTile / 2) << n) top = n;
  if (top < 0) throw_not_toast(4 * height, height);
  const int deepest = options.levels < 0 ? top : options.levels;
  if (deepest > top)
    throw UsageError(fmt::format("--levels {} needs a PQ height of {} (this one, {}, reaches level {})", deepest,
                                 (kTile / 2) << deepest, height, top));
  if (fs::exists(dir) && !(fs::is_directory(dir) && fs::is_empty(dir)))
    throw UsageError(dir.string() + ": exists and is not an empty directory");
  // Built next to the destination, renamed at the end: no partial pyramid is ever visible.
  io::write_staged_directory(dir, [&](const fs::path& temp) {
    StripPyramid pyramid(temp, deepest, channels, options.write);
    // 2^(top - deepest) square rows average to one row of the deepest level written.
    const int n = 2 * height, fold = 1 << (top - deepest);
    Image chunk(n, fold, channels);
    std::vector<float> row(static_cast<std::size_t>(channels) * n);
    for (int y = 0; y < n; ++y) {
      rows(y, row);
      for (int c = 0; c < channels; ++c)
        std::copy_n(row.data() + static_cast<std::size_t>(c) * n, n, &chunk.at(c, 0, y % fold));
      if (y % fold != fold - 1) continue;
      Image level = chunk;
      while (level.height > 1) level = halve(level);
      pyramid.add(deepest, level);
    }
    write_wtml(temp / "toast.wtml", options.name, deepest);
  });
}

}  // namespace gdp::sphere
