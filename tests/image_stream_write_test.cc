// Streaming image output (ImageFileWriter): round trips, tiles, failures that leave nothing, and bounded memory.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <csignal>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <set>
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
using test::pattern;

// Writes `image` row by row.
void stream_write(const fs::path& p, const Image& image, const WriteOptions& options, bool write_behind) {
  ImageFileWriter writer(p, image.width, image.height, image.channels, options, write_behind);
  const auto rows = test::rows_of(image);
  for (int y = 0; y < image.height; ++y) writer.write_row(y, rows[y]);
  writer.commit();
}

class ImageStreamWrite : public test::TempDirTest {};

TEST_F(ImageStreamWrite, StreamedWritesReadBackAsWritten) {
  struct Case {
    const char* name;
    std::optional<SampleType> type;
    float tolerance;  // 0: exact to a few ulps
  };
  const Image image = pattern(300, 700, 3);  // several bands
  ASSERT_LT(io::band_rows(300, 700, 3), 700);
  Image smooth(300, 700, 3);  // for JPEG, whose chroma subsampling blurs the pattern's colour edges
  for (int c = 0; c < 3; ++c)
    for (int y = 0; y < 700; ++y)
      for (int x = 0; x < 300; ++x) smooth.at(c, x, y) = 0.2f + 0.6f * static_cast<float>(x + y + 50 * c) / 1100.0f;
  for (const Case& k : {Case{"8.png", SampleType::UInt8, 0}, Case{"16.png", SampleType::UInt16, 0},
                        Case{"16.tif", SampleType::UInt16, 0}, Case{"float.tif", SampleType::Float, 0},
                        Case{"float.exr", SampleType::Float, 0}, Case{"half.exr", SampleType::Half, 1e-3f},
                        Case{"float.fits", SampleType::Float, 0}, Case{"a.jpg", std::nullopt, 0.03f}})
    for (bool write_behind : {true, false}) {
      SCOPED_TRACE(::testing::Message() << k.name << (write_behind ? " write-behind" : " direct"));
      WriteOptions options;
      options.sample_type = k.type;
      const Image& source = std::string(k.name) == "a.jpg" ? smooth : image;
      stream_write(dir_ / k.name, source, options, write_behind);
      const Image back = read_image(dir_ / k.name).image;
      ASSERT_EQ(back.data.size(), source.data.size());
      double total = 0.0;
      for (std::size_t i = 0; i < source.data.size(); ++i) {
        if (k.tolerance == 0) {
          ASSERT_FLOAT_EQ(back.data[i], source.data[i]) << "sample " << i;
        } else {
          ASSERT_NEAR(back.data[i], source.data[i], k.tolerance) << "sample " << i;
        }
        total += std::abs(back.data[i] - source.data[i]);
      }
      EXPECT_LT(total / static_cast<double>(source.data.size()), 0.005);
    }
  EXPECT_EQ(names().size(), 8u) << "no temporary file is left";
}

// TIFF strips are assembled where the writer puts the converted rows (io::Encoder::row_space):
// bands of 29 rows across strips of 32, a last strip of 4 rows, every compression and sample type
// (doubles are widened, so copied); written with and without write-behind, the same bytes.
TEST_F(ImageStreamWrite, TiffStripsBuiltInPlaceReadBackForEveryCompression) {
  const Image image = pattern(3000, 100, 3);
  ASSERT_EQ(io::band_rows(3000, 100, 3), 29);
  for (const char* compression : {"none", "lzw", "packbits", "zip"})
    for (SampleType type : {SampleType::UInt8, SampleType::UInt16, SampleType::Float, SampleType::Double}) {
      SCOPED_TRACE(::testing::Message() << compression << " type " << static_cast<int>(type));
      WriteOptions options;
      options.sample_type = type;
      options.compression = compression;
      const float step = type == SampleType::UInt8 ? 0.5f / 255 : type == SampleType::UInt16 ? 0.5f / 65535 : 0.0f;
      std::string bytes[2];
      for (bool write_behind : {true, false}) {
        const fs::path p = dir_ / (write_behind ? "behind.tif" : "direct.tif");
        stream_write(p, image, options, write_behind);
        const Image back = read_image(p).image;
        ASSERT_EQ(back.data.size(), image.data.size());
        for (std::size_t i = 0; i < image.data.size(); ++i)
          ASSERT_NEAR(back.data[i], image.data[i], step * 1.0001f) << "sample " << i;
        std::ifstream in(p, std::ios::binary);
        bytes[write_behind] = std::string(std::istreambuf_iterator<char>(in), {});
      }
      EXPECT_EQ(bytes[0], bytes[1]);
    }
}

TEST_F(ImageStreamWrite, TiledOutputIsTiledAndReadsBackTheSame) {
  const Image image = pattern(300, 200, 2);  // partial tiles at the right and bottom
  for (const char* name : {"a.tif", "a.exr"}) {
    WriteOptions options;
    options.tiled = true;
    options.tile_size = 64;
    stream_write(dir_ / name, image, options, true);
    auto in = OIIO::ImageInput::open((dir_ / name).string());
    ASSERT_TRUE(in);
    EXPECT_EQ(in->spec().tile_width, 64) << name;
    EXPECT_EQ(in->spec().tile_height, 64) << name;
    in.reset();
    EXPECT_EQ(read_image(dir_ / name).image.data, image.data) << name;
  }
  WriteOptions options;
  options.tiled = true;
  try {
    ImageFileWriter writer(dir_ / "a.png", 10, 10, 1, options);
    FAIL() << "tiled PNG accepted";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find(".tif or .exr"), std::string::npos) << e.what();
  }
  options.tile_size = 40;
  EXPECT_THROW(ImageFileWriter(dir_ / "b.tif", 10, 10, 1, options), OutputError);
  EXPECT_EQ(names(), (std::set<std::string>{"a.exr", "a.tif"}));
}

TEST_F(ImageStreamWrite, WritersNotCommittedLeaveNothing) {
  const Image image = pattern(300, 900, 3);
  const auto rows = test::rows_of(image);
  for (bool write_behind : {true, false})
    for (int stop : {0, 1, 450, 900}) {
      ImageFileWriter writer(dir_ / "out.tif", 300, 900, 3, {}, write_behind);
      for (int y = 0; y < stop; ++y) writer.write_row(y, rows[y]);
      if (stop < 900) {
        EXPECT_THROW(writer.commit(), OutputError) << "commit after " << stop << " rows";
      }
    }
  EXPECT_TRUE(names().empty());
  ImageFileWriter writer(dir_ / "out.png", 300, 900, 3, {});
  EXPECT_THROW(writer.write_row(1, rows[1]), std::logic_error);
  EXPECT_THROW(writer.write_row(0, std::vector<float>(899)), std::logic_error);
  for (int y = 0; y < 900; ++y) writer.write_row(y, rows[y]);
  EXPECT_THROW(writer.write_row(900, rows[0]), std::logic_error);
  writer.commit();
  EXPECT_THROW(writer.commit(), std::logic_error);
  EXPECT_EQ(names(), std::set<std::string>{"out.png"});
}

// A disk that fills up: files may not grow past `bytes` while this lives (SIGXFSZ ignored, so
// writes fail with EFBIG instead of killing the process).
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) : old_signal_(std::signal(SIGXFSZ, SIG_IGN)) {
    getrlimit(RLIMIT_FSIZE, &old_);
    rlimit limit = old_;
    limit.rlim_cur = bytes;
    setrlimit(RLIMIT_FSIZE, &limit);
  }
  ~FileSizeLimit() {
    setrlimit(RLIMIT_FSIZE, &old_);
    std::signal(SIGXFSZ, old_signal_);
  }

 private:
  rlimit old_{};
  void (*old_signal_)(int);
};

TEST_F(ImageStreamWrite, AFullDiskIsAnOutputErrorAndLeavesNothing) {
  // Incompressible pixels: every format needs far more than the 64 KiB allowed. OpenImageIO
  // 2.4's PNG and BMP writers ignore failed writes and its JPEG writer calls exit() on one.
  Image noise(400, 300, 3);
  std::mt19937 random(7);
  for (float& v : noise.data) v = static_cast<float>(random() % 256) / 255.0f;
  for (const char* name : {"a.png", "a.bmp", "a.jpg", "a.tif", "a.exr"})
    for (bool write_behind : {true, false}) {
      SCOPED_TRACE(::testing::Message() << name << (write_behind ? " write-behind" : " direct"));
      const FileSizeLimit limit(64 * 1024);
      try {
        stream_write(dir_ / name, noise, {}, write_behind);
        ADD_FAILURE() << "no error";
      } catch (const OutputError& e) {
        EXPECT_NE(std::string(e.what()).find((dir_ / name).string() + ": cannot write"), std::string::npos) << e.what();
      }
      EXPECT_TRUE(names().empty());
    }
}

// Growth of the process's peak resident memory since construction. The kernel's peak mark is
// reset first where Linux allows it (/proc/self/clear_refs), so earlier tests cannot hide growth;
// elsewhere this falls back to getrusage()'s ru_maxrss.
class PeakGrowth {
 public:
  PeakGrowth() : resettable_(static_cast<bool>(std::ofstream("/proc/self/clear_refs") << "5")), base_(peak_kb()) {}
  double megabytes() const { return static_cast<double>(peak_kb() - base_) / 1024.0; }

 private:
  long peak_kb() const {
    if (resettable_) {
      std::ifstream status("/proc/self/status");
      for (std::string line; std::getline(status, line);)
        if (line.rfind("VmHWM:", 0) == 0) return std::stol(line.substr(6));
    }
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return usage.ru_maxrss;
  }
  bool resettable_;
  long base_;
};

TEST_F(ImageStreamWrite, TallImagesStreamInBoundedMemory) {
  // 256 x 160000 in one 8-bit channel: 41 MB as stored (82 MB as OpenEXR's half), 164 MB as
  // floats. Writing and reading it row by row must grow the peak by far less than any of them.
  const int w = 256, h = 160000;
  std::vector<float> row(w);
  const auto value = [](int x, int y) { return static_cast<float>((x + 3 * y) % 256) / 255.0f; };
  for (const char* name : {"tall.tif", "tall.png", "tall.exr"}) {
    SCOPED_TRACE(name);
    const bool half = std::string(name).ends_with(".exr");  // 8-bit samples are written to OpenEXR as half
    const fs::path p = dir_ / name;
    WriteOptions options;
    options.sample_type = SampleType::UInt8;
    {
      const PeakGrowth growth;
      ImageFileWriter writer(p, w, h, 1, options);
      for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) row[x] = value(x, y);
        writer.write_row(y, row);
      }
      writer.commit();
      EXPECT_LT(growth.megabytes(), 20.0) << "writing";
    }
    const PeakGrowth growth;
    ImageFileReader reader(p);
    for (int y = 0; y < h; ++y) {
      reader.read_row(y, row);
      for (int x = 0; x < w; x += 37)
        ASSERT_FLOAT_EQ(row[x], half ? static_cast<float>(static_cast<_Float16>(value(x, y))) : value(x, y)) << x << " " << y;
    }
    EXPECT_LT(growth.megabytes(), 20.0) << "reading";
  }
}

}  // namespace
}  // namespace gdp
