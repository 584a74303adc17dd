// Streaming image files: rows read and written by ImageFileReader/Writer against OpenImageIO's own whole-image I/O.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "gdp/errors.h"
#include "gdp/image_io.h"
#include "gdp/image_stream.h"
#include "image_stream_util.h"
#include "io/codec_util.h"

namespace gdp {
namespace {

namespace fs = std::filesystem;
using test::oiio_read;
using test::pattern;
using test::oiio_write;
using test::rows_of;

// Every row of `reader` in order, compared with `expected`; `rows` rows only when given.
void expect_rows(ImageFileReader& reader, const Image& expected, int rows = -1) {
  std::vector<float> row(static_cast<std::size_t>(expected.width) * expected.channels);
  const std::vector<std::vector<float>> want = rows_of(expected);
  for (int y = 0; y < (rows < 0 ? expected.height : rows); ++y) {
    reader.read_row(y, row);
    ASSERT_EQ(row, want[y]) << "row " << y;
  }
}

class ImageStream : public test::TempDirTest {};

TEST_F(ImageStream, StreamedRowsEqualWholeImageReadsForEveryFormat) {
  struct Case {
    const char* name;
    OIIO::TypeDesc type;
    int channels, tile;
  };
  // 257 x 1500: several bands per file (and several tile rows, with a partial one at the bottom).
  const int w = 257, h = 1500;
  for (const Case& k : {Case{"8.png", OIIO::TypeDesc::UINT8, 3, 0}, Case{"16.png", OIIO::TypeDesc::UINT16, 4, 0},
                        Case{"a.jpg", OIIO::TypeDesc::UINT8, 3, 0}, Case{"strips.tif", OIIO::TypeDesc::UINT16, 2, 0},
                        Case{"tiles.tif", OIIO::TypeDesc::FLOAT, 3, 64}, Case{"tiles8.tif", OIIO::TypeDesc::UINT8, 1, 16},
                        Case{"rgba8.tif", OIIO::TypeDesc::UINT8, 4, 0}, Case{"grey16.tif", OIIO::TypeDesc::UINT16, 1, 0},
                        Case{"a.exr", OIIO::TypeDesc::FLOAT, 3, 0},
                        Case{"tiles.exr", OIIO::TypeDesc::HALF, 1, 32}}) {  // FITS: fits_test.cc
    SCOPED_TRACE(k.name);
    ASSERT_LT(io::band_rows(w, h, k.channels, std::max(k.tile, 1)), h) << "the file must span several bands";
    const fs::path p = dir_ / k.name;
    oiio_write(p, pattern(w, h, k.channels), k.type, k.tile);
    const Image expected = oiio_read(p);
    EXPECT_EQ(read_image(p).image.data, expected.data);
    for (bool prefetch : {true, false}) {
      SCOPED_TRACE(prefetch ? "prefetch" : "no prefetch");
      ImageFileReader reader(p, prefetch);
      ASSERT_EQ(reader.width(), w);
      ASSERT_EQ(reader.height(), h);
      ASSERT_EQ(reader.channels(), k.channels);
      EXPECT_EQ(reader.info().format_name, read_image(p).info.format_name);
      expect_rows(reader, expected);
      reader.rewind();  // after a whole pass
      expect_rows(reader, expected);
      reader.rewind();
      expect_rows(reader, expected, h / 2);
      reader.rewind();  // in the middle of a pass
      expect_rows(reader, expected);
    }
  }
}

TEST_F(ImageStream, RewindOfAnImageInOneBandRepeatsIt) {
  const fs::path p = dir_ / "small.png";
  oiio_write(p, pattern(31, 17, 3), OIIO::TypeDesc::UINT8);
  const Image expected = oiio_read(p);
  for (bool prefetch : {true, false}) {
    ImageFileReader reader(p, prefetch);
    for (int pass = 0; pass < 3; ++pass, reader.rewind()) expect_rows(reader, expected);
  }
}

TEST_F(ImageStream, RowsMustBeReadInOrderIntoLargeEnoughBuffers) {
  const fs::path p = dir_ / "a.tif";
  oiio_write(p, pattern(40, 30, 2), OIIO::TypeDesc::UINT8);
  for (bool prefetch : {true, false}) {
    ImageFileReader reader(p, prefetch);
    std::vector<float> row(80), short_row(79);
    EXPECT_THROW(reader.read_row(1, row), std::logic_error);
    EXPECT_THROW(reader.read_row(0, short_row), std::logic_error);
    reader.read_row(0, row);
    EXPECT_THROW(reader.read_row(0, row), std::logic_error);
    EXPECT_THROW(reader.read_row(2, row), std::logic_error);
    for (int y = 1; y < 30; ++y) reader.read_row(y, row);
    EXPECT_THROW(reader.read_row(30, row), std::logic_error);
  }
}

TEST_F(ImageStream, OpenErrorsAreTheSameAsReadImages) {
  std::ofstream(dir_ / "text.png") << "plain text, not a PNG\n";
  oiio_write(dir_ / "five.tif", Image(4, 3, 5), OIIO::TypeDesc::UINT8);
  for (const fs::path& p : {dir_ / "missing.png", dir_ / "text.png", dir_ / "five.tif", dir_}) {
    std::string expected;
    try {
      read_image(p);
    } catch (const InputError& e) {
      expected = e.what();
    }
    ASSERT_NE(expected.find(p.string()), std::string::npos) << expected;
    try {
      ImageFileReader reader(p);
      ADD_FAILURE() << "opened " << p;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()), expected);
    }
  }
}

TEST_F(ImageStream, ReadersDestroyedAnywhereStopCleanly) {
  const fs::path p = dir_ / "a.png";
  oiio_write(p, pattern(300, 2000, 3), OIIO::TypeDesc::UINT8);
  std::vector<float> row(900);
  for (int rows : {0, 1, 500, 1999}) {
    ImageFileReader reader(p, true);
    for (int y = 0; y < rows; ++y) reader.read_row(y, row);
  }  // a hang or crash here fails the test
  ImageFileReader reader(p, true);
  reader.read_row(0, row);
  reader.rewind();
  reader.read_row(0, row);
}

TEST_F(ImageStream, ADecodeErrorNamesTheFileAndStaysAnError) {
  // Incompressible pixels, so the cut falls in the middle of the image data (a later band).
  const fs::path p = dir_ / "cut.png";
  Image noise(400, 1000, 3);
  std::mt19937 random(7);
  for (float& v : noise.data) v = static_cast<float>(random() % 256) / 255.0f;
  oiio_write(p, noise, OIIO::TypeDesc::UINT8);
  fs::resize_file(p, fs::file_size(p) * 6 / 10);
  for (bool prefetch : {true, false}) {
    SCOPED_TRACE(prefetch ? "prefetch" : "no prefetch");
    ImageFileReader reader(p, prefetch);
    std::vector<float> row(1200);
    int y = 0;
    try {
      for (; y < 1000; ++y) reader.read_row(y, row);
      FAIL() << "a truncated file read to the end";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(p.string()), std::string::npos) << e.what();
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    }
    EXPECT_GT(y, 0) << "the first band is intact";
    EXPECT_LT(y, 1000);
    EXPECT_THROW(reader.read_row(y, row), InputError) << "no rows after a failed band";
  }
}

}  // namespace
}  // namespace gdp
