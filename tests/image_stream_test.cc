// Streaming image files: row readers and writers against whole-image I/O, failures, memory.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <filesystem>
#include <vector>

#include "gdp/errors.h"
#include "gdp/image_io.h"
#include "gdp/image_stream.h"
#include "test_util.h"

namespace gdp {
namespace {

namespace fs = std::filesystem;

class ImageStream : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("gdp-image-stream-" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

std::vector<float> row_of(const Image& img, int y) {
  std::vector<float> r(static_cast<std::size_t>(img.width) * img.channels);
  ImageRowReader(img).read_row(y, r);
  return r;
}

TEST_F(ImageStream, RowsMatchTheWholeImageAndRewindRepeatsThem) {
  const Image img = test::random_image(300, 120, 3, 4);
  for (const char* name : {"a.tif", "a.exr", "a.png"}) {
    const fs::path p = dir_ / name;
    WriteOptions wo;
    wo.sample_type = SampleType::UInt16;
    write_image(p, img, wo);
    const Image whole = read_image(p).image;
    for (bool prefetch : {false, true}) {
      ImageFileReader reader(p, prefetch);
      std::vector<float> row(300 * 3);
      for (int pass = 0; pass < 2; ++pass) {
        for (int y = 0; y < 120; ++y) {
          reader.read_row(y, row);
          ASSERT_EQ(row, row_of(whole, y)) << name << " row " << y << " pass " << pass;
        }
        reader.rewind();
      }
      EXPECT_THROW(reader.read_row(5, row), std::logic_error) << "rows are read in order";
    }
  }
}

TEST_F(ImageStream, TiledOutputIsTiledAndReadsBackTheSame) {
  const Image img = test::random_image(700, 300, 2, 6);
  const fs::path p = dir_ / "tiled.tif";
  WriteOptions wo;
  wo.tiled = true;
  write_image(p, img, wo);
  auto in = OIIO::ImageInput::open(p.string());
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().tile_width, 256);
  in.reset();
  EXPECT_EQ(read_image(p).image.data, img.data);
  wo.tiled = true;
  EXPECT_THROW(write_image(dir_ / "tiled.png", img, wo), OutputError);
  EXPECT_FALSE(fs::exists(dir_ / "tiled.png"));
}

TEST_F(ImageStream, AWriterNotCommittedLeavesNothing) {
  {
    ImageFileWriter w(dir_ / "out.tif", 50, 40, 1, {});
    std::vector<float> row(50, 0.5f);
    for (int y = 0; y < 20; ++y) w.write_row(y, row);
    EXPECT_THROW(w.commit(), OutputError);  // only half the rows
  }
  EXPECT_TRUE(fs::is_empty(dir_));
}

TEST_F(ImageStream, ADecodeErrorOnTheReaderThreadNamesTheFile) {
  const fs::path p = dir_ / "cut.png";
  write_image(p, test::random_image(400, 400, 3, 8), {});
  fs::resize_file(p, fs::file_size(p) / 2);
  ImageFileReader reader(p, true);
  std::vector<float> row(400 * 3);
  try {
    for (int y = 0; y < 400; ++y) reader.read_row(y, row);
    FAIL() << "a truncated file read to the end";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cut.png"), std::string::npos) << e.what();
  }
}

TEST_F(ImageStream, ReadingATallImageHoldsOnlyBands) {
  // 512 x 60000 single-channel 8-bit TIFF: 123 MB as floats; streamed, memory must not grow so.
  const int w = 512, h = 60000;
  const fs::path p = dir_ / "tall.tif";
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  const long before = u.ru_maxrss;  // writing and reading both stream
  {
    WriteOptions wo;
    wo.sample_type = SampleType::UInt8;
    ImageFileWriter out(p, w, h, 1, wo);
    std::vector<float> row(w);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) row[x] = static_cast<float>((x + y) % 256) / 255.0f;
      out.write_row(y, row);
    }
    out.commit();
  }
  ImageFileReader in(p);
  std::vector<float> row(w);
  double sum = 0.0;
  for (int y = 0; y < h; ++y) {
    in.read_row(y, row);
    sum += row[y % w];
  }
  getrusage(RUSAGE_SELF, &u);
  EXPECT_GT(sum, 0.0);
  EXPECT_LT((u.ru_maxrss - before) / 1024, 30) << "peak memory grew while writing or reading";
}

}  // namespace
}  // namespace gdp
