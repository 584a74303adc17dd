// ImageFileReader's column window: the window's slice of every row, and tiled TIFFs and OpenEXRs decoding only the tiles it overlaps.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <tuple>
#include <utility>
#include <vector>

#include "gdp/errors.h"
#include "gdp/image_io.h"
#include "gdp/image_stream.h"
#include "image_stream_util.h"
#include "io/codecs.h"

namespace gdp {
namespace {

namespace fs = std::filesystem;
using test::oiio_write;
using test::pattern;

// Bytes this process has read through read() and pread() so far (/proc/self/io's rchar).
long long bytes_read() {
  std::ifstream io("/proc/self/io");
  std::string key;
  long long value = 0;
  while (io >> key >> value)
    if (key == "rchar:") return value;
  return -1;
}

// An uncompressed TIFF in strips of `rows` rows.
void write_raw_strips(const fs::path& p, const Image& image, OIIO::TypeDesc type, int rows) {
  test::oiio_write_with(p, image, type, [rows](OIIO::ImageSpec& spec) {
    spec.attribute("compression", "none");
    spec.attribute("tiff:RowsPerStrip", rows);
  });
}

class ColumnWindow : public test::TempDirTest {
 protected:
  // Every row of the window [x0, x1) equals the same columns of the whole image.
  static void expect_window(const fs::path& p, int x0, int x1, bool prefetch) {
    SCOPED_TRACE(::testing::Message() << p.filename() << " [" << x0 << ", " << x1 << ")");
    const Image whole = read_image(p).image;
    ImageFileReader reader(p, prefetch, ColumnRange{x0, x1});
    const int w = (x1 < 0 ? whole.width : x1) - x0;
    ASSERT_EQ(reader.width(), whole.width);
    ASSERT_EQ(reader.window_begin(), x0);
    ASSERT_EQ(reader.window_width(), w);
    std::vector<float> row(static_cast<std::size_t>(w) * whole.channels);
    for (int y = 0; y < whole.height; ++y) {
      reader.read_row(y, row);
      for (int c = 0; c < whole.channels; ++c)
        for (int x = 0; x < w; ++x)
          ASSERT_EQ(row[static_cast<std::size_t>(c) * w + x], whole.at(c, x0 + x, y)) << "row " << y << " x " << x;
    }
  }
};

TEST_F(ColumnWindow, EveryFormatGivesTheWindowsColumns) {
  struct Case {
    const char* name;
    OIIO::TypeDesc type;
    int channels, tile;
  };
  // 300 x 900: several bands; windows inside tiles, across tile edges, at both image edges.
  for (const Case& k : {Case{"a.png", OIIO::TypeDesc::UINT16, 4, 0}, Case{"a.jpg", OIIO::TypeDesc::UINT8, 3, 0},
                        Case{"strips.tif", OIIO::TypeDesc::UINT8, 2, 0}, Case{"tiles.tif", OIIO::TypeDesc::FLOAT, 3, 64},
                        Case{"a.exr", OIIO::TypeDesc::HALF, 3, 0}, Case{"tiles.exr", OIIO::TypeDesc::FLOAT, 1, 32}}) {
    const fs::path p = dir_ / k.name;
    oiio_write(p, pattern(300, 900, k.channels), k.type, k.tile);
    for (auto [x0, x1] : {std::pair{0, -1}, std::pair{0, 1}, std::pair{70, 100}, std::pair{60, 200}, std::pair{250, 300},
                          std::pair{299, 300}})
      expect_window(p, x0, x1, x0 % 20 == 0);
  }
}

// Uncompressed strips are read as the file's bytes (io/tiff_decoder.cc, read_raw): every sample
// type, strips that end inside the image, windows anywhere.
TEST_F(ColumnWindow, UncompressedStripsOfEverySampleTypeGiveTheWindowsColumns) {
  for (auto [type, channels, rows] : {std::tuple{OIIO::TypeDesc::UINT8, 3, 7}, std::tuple{OIIO::TypeDesc::UINT16, 1, 64},
                                      std::tuple{OIIO::TypeDesc::HALF, 2, 5}, std::tuple{OIIO::TypeDesc::FLOAT, 4, 900},
                                      std::tuple{OIIO::TypeDesc::DOUBLE, 1, 1}}) {
    SCOPED_TRACE(OIIO::TypeDesc(type).c_str());
    const fs::path p = dir_ / "raw.tif";
    write_raw_strips(p, pattern(300, 900, channels), type, rows);
    for (auto [x0, x1] : {std::pair{0, -1}, std::pair{0, 1}, std::pair{70, 100}, std::pair{250, 300}, std::pair{299, 300}})
      expect_window(p, x0, x1, x0 % 20 == 0);
  }
}

// A narrow window of uncompressed strips reads about its own bytes, not whole rows (what a rank of
// a distributed solve reads of an uncompressed TIFF).
TEST_F(ColumnWindow, UncompressedStripsReadOnlyTheWindowsBytes) {
  const fs::path p = dir_ / "raw.tif";
  write_raw_strips(p, pattern(2000, 300, 3), OIIO::TypeDesc::UINT8, 16);  // 1.8 MB of samples
  ASSERT_GE(bytes_read(), 0) << "no /proc/self/io";
  const auto read = [&](ColumnRange window) {
    const long long before = bytes_read();
    ImageFileReader reader(p, false, window);
    std::vector<float> row(static_cast<std::size_t>(reader.window_width()) * 3);
    for (int y = 0; y < reader.height(); ++y) reader.read_row(y, row);
    return bytes_read() - before;
  };
  EXPECT_GE(read({}), 2000 * 300 * 3);
  EXPECT_LT(read({1000, 1100}), 2000 * 300 * 3 / 10);  // a 20th of the columns
}

TEST_F(ColumnWindow, TiledFilesDecodeOnlyTheTilesTheWindowOverlaps) {
  for (auto [name, tiles_decoded] : {std::pair{"tiles.tif", &io::tiff_tiles_decoded}, std::pair{"tiles.exr", &io::exr_tiles_decoded}}) {
    SCOPED_TRACE(name);
    const fs::path p = dir_ / name;
    oiio_write(p, pattern(512, 256, 3), OIIO::TypeDesc::UINT8, 64);  // 8 x 4 tiles
    auto count = [&](ColumnRange window) {
      const long before = tiles_decoded();
      ImageFileReader reader(p, false, window);
      std::vector<float> row(static_cast<std::size_t>(reader.window_width()) * 3);
      for (int y = 0; y < reader.height(); ++y) reader.read_row(y, row);
      return tiles_decoded() - before;
    };
    EXPECT_EQ(count({}), 32);
    EXPECT_EQ(count({64, 128}), 4);   // one tile column
    EXPECT_EQ(count({100, 180}), 8);  // two tile columns, neither whole
    EXPECT_EQ(count({511, 512}), 4);
  }
}

// RowReader::set_columns (a rank of a distributed solve): the window's columns at their place in
// full rows, the other samples untouched, and only the overlapping tiles decoded.
TEST_F(ColumnWindow, SetColumnsFillsTheWindowInPlace) {
  const fs::path p = dir_ / "tiles.tif";
  const Image whole = pattern(300, 200, 2);
  oiio_write(p, whole, OIIO::TypeDesc::FLOAT, 64);
  ImageFileReader reader(p);
  const long before = io::tiff_tiles_decoded();
  reader.set_columns(70, 130);  // tiles 1 and 2 of 5 per tile row
  std::vector<float> row(2 * 300, -1.0f);
  for (int y = 0; y < 200; ++y) {
    reader.read_row(y, row);
    for (int c = 0; c < 2; ++c)
      for (int x = 70; x < 130; ++x) ASSERT_EQ(row[c * 300 + x], whole.at(c, x, y)) << x << " " << y;
  }
  EXPECT_EQ(row[0], -1.0f);
  EXPECT_EQ(row[300 + 299], -1.0f);
  EXPECT_EQ(io::tiff_tiles_decoded() - before, 2 * 4) << "two tile columns of four tile rows";
  EXPECT_THROW(reader.set_columns(0, 10), std::logic_error) << "rows were read already";
}

// read_ahead() starts decoding before the first row: the rows are the same, and a set_columns()
// after it (the bands decoded by then, if any, dropped) still gives the window. Without prefetch
// it does nothing.
TEST_F(ColumnWindow, ReadAheadThenRowsOrAWindowAreTheSame) {
  const fs::path p = dir_ / "a.png";  // PNG decodes forwards only: a window after decoding reopens it
  oiio_write(p, pattern(300, 900, 3), OIIO::TypeDesc::UINT16);
  const Image whole = read_image(p).image;
  for (bool prefetch : {true, false}) {
    SCOPED_TRACE(prefetch ? "prefetch" : "no prefetch");
    ImageFileReader all(p, prefetch), window(p, prefetch);
    all.read_ahead();
    window.read_ahead();
    window.set_columns(70, 130);
    std::vector<float> row(3 * 300, -1.0f), cut(3 * 300, -1.0f);
    for (int y = 0; y < 900; ++y) {
      all.read_row(y, row);
      window.read_row(y, cut);
      for (int c = 0; c < 3; ++c)
        for (int x = 0; x < 300; ++x) {
          ASSERT_EQ(row[c * 300 + x], whole.at(c, x, y)) << x << " " << y;
          if (x >= 70 && x < 130) {
            ASSERT_EQ(cut[c * 300 + x], whole.at(c, x, y)) << x << " " << y;
          }
        }
    }
    EXPECT_EQ(cut[0], -1.0f) << "columns outside the window are left as they are";
  }
}

// After read_ahead(bytes) the decoding thread runs that far ahead of a caller who reads nothing
// (as many bands as fit, at least two queued, one more decoded and waiting for room), then stops;
// the rows are the same whatever the depth. A 64-wide 8-bit file has bands of 4,096 rows (256 KiB).
TEST_F(ColumnWindow, ReadAheadDecodesAsFarAheadAsItsBytes) {
  const fs::path p = dir_ / "tall.png";
  const int bands = 10, band = 4096, h = bands * band;
  oiio_write(p, pattern(64, h, 1), OIIO::TypeDesc::UINT8);
  const Image whole = read_image(p).image;
  const std::pair<std::size_t, int> cases[] = {
      {0, 3 * band},                           // two bands queued (as without read_ahead), one waiting
      {std::size_t{1} << 20, 5 * band},        // four queued, one waiting
      {ImageFileReader::kAheadBytes, h}};      // 32 bands: the whole image
  for (const auto& [bytes, rows] : cases) {
    SCOPED_TRACE(::testing::Message() << bytes << " bytes ahead");
    ImageFileReader reader(p);
    EXPECT_EQ(reader.decoded_rows(), 0);
    reader.read_ahead(bytes);
    for (int i = 0; i < 6000 && reader.decoded_rows() < rows; ++i)  // waits up to a minute, then fails
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    std::this_thread::sleep_for(std::chrono::milliseconds(50));  // had it gone further, it would be now
    EXPECT_EQ(reader.decoded_rows(), rows);
    std::vector<float> row(64);
    for (int y = 0; y < h; ++y) {
      reader.read_row(y, row);
      for (int x = 0; x < 64; ++x) ASSERT_EQ(row[x], whole.at(0, x, y)) << x << " " << y;
    }
    EXPECT_EQ(reader.decoded_rows(), h);
  }
}

TEST_F(ColumnWindow, WindowsOutsideTheImageAreInputErrors) {
  const fs::path p = dir_ / "a.png";
  oiio_write(p, pattern(30, 20, 1), OIIO::TypeDesc::UINT8);
  for (auto [x0, x1] : {std::pair{-1, 10}, std::pair{10, 31}, std::pair{10, 10}, std::pair{20, 5}}) {
    try {
      ImageFileReader reader(p, true, ColumnRange{x0, x1});
      ADD_FAILURE() << "no error for [" << x0 << ", " << x1 << ")";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(p.string()), std::string::npos) << e.what();
    }
  }
}

TEST_F(ColumnWindow, RewindReadsTheSameWindowAgain) {
  const fs::path p = dir_ / "tall.tif";
  oiio_write(p, pattern(200, 3000, 3), OIIO::TypeDesc::UINT16, 32);
  ImageFileReader reader(p, true, ColumnRange{40, 90});
  std::vector<float> first(50 * 3), again(50 * 3);
  for (int y = 0; y < 3000; ++y) reader.read_row(y, first);
  reader.rewind();
  for (int y = 0; y < 3000; ++y) reader.read_row(y, again);
  EXPECT_EQ(first, again);
  const Image whole = read_image(p).image;
  EXPECT_EQ(again[2 * 50 + 7], whole.at(2, 47, 2999));
}

}  // namespace
}  // namespace gdp
