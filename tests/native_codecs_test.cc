// gdp's own PNG, TIFF and JPEG codecs: the same pixels and file info as OpenImageIO, and round trips per sample type.
#include <OpenImageIO/imageio.h>
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "codec_test_util.h"
#include "gdp/errors.h"
#include "gdp/image_io.h"
#include "gdp/image_stream.h"
#include "image_stream_util.h"
#include "io/codec_util.h"
#include "io/codecs.h"

namespace gdp {
namespace {

namespace fs = std::filesystem;
using test::expect_same;
using test::oiio_read;
using test::oiio_write_with;
using test::pattern;

class NativeCodecs : public test::TempDirTest {
 protected:
  // gdp reads `p` with its own decoder (not OpenImageIO's module), with the pixels, sample type
  // and format name OpenImageIO reports.
  void expect_native_like_oiio(const fs::path& p) {
    SCOPED_TRACE(p.string());
    EXPECT_TRUE(native(p)) << "left to OpenImageIO";
    const ReadResult ours = read_image(p);
    expect_same(oiio_read(p), ours.image, p.filename().string());
    EXPECT_EQ(ours.info.sample_type, test::oiio_sample_type(p));
    EXPECT_EQ(ours.info.format_name, test::oiio_format_name(p));
    EXPECT_EQ(ours.info.lossy, ours.info.format_name == "jpeg");
  }

  static bool native(const fs::path& p) {
    const std::string ext = io::lower_extension(p.string());
    if (ext == "png") return io::open_png_decoder(p.string()) != nullptr;
    if (ext == "tif" || ext == "tiff") return io::open_tiff_decoder(p.string()) != nullptr;
    return io::open_jpeg_decoder(p.string()) != nullptr;
  }
};

TEST_F(NativeCodecs, PngFromOpenImageIOReadsTheSame) {
  for (OIIO::TypeDesc type : {OIIO::TypeDesc::UINT8, OIIO::TypeDesc::UINT16})
    for (int channels = 1; channels <= 4; ++channels) {
      const fs::path p = dir_ / fmt::format("c{}_{}.png", channels, type.size());
      oiio_write_with(p, pattern(61, 47, channels), type, [](OIIO::ImageSpec&) {});
      expect_native_like_oiio(p);
    }
}

TEST_F(NativeCodecs, PngVariantsExpandAsOpenImageIODoes) {
  const int w = 19, h = 13;
  auto make = [&](int color, int depth, int bytes_per_row) {
    test::PngVariant v;
    v.width = w;
    v.height = h;
    v.color = color;
    v.depth = depth;
    for (int y = 0; y < h; ++y) {
      std::vector<png_byte> row(static_cast<std::size_t>(bytes_per_row));
      for (int i = 0; i < bytes_per_row; ++i) row[i] = static_cast<png_byte>((i * 37 + y * 11) % 256);
      v.rows.push_back(row);
    }
    return v;
  };
  struct Case {
    const char* name;
    int color, depth, row_bytes;
    bool palette, alpha_palette, trans, interlaced;
  };
  for (const Case& k : {Case{"pal8.png", PNG_COLOR_TYPE_PALETTE, 8, w, true, false, false, false},
                        Case{"pal4_trns.png", PNG_COLOR_TYPE_PALETTE, 4, (w + 1) / 2, true, true, false, false},
                        Case{"pal1.png", PNG_COLOR_TYPE_PALETTE, 1, (w + 7) / 8, true, false, false, true},
                        Case{"gray1.png", PNG_COLOR_TYPE_GRAY, 1, (w + 7) / 8, false, false, false, false},
                        Case{"gray2.png", PNG_COLOR_TYPE_GRAY, 2, (w + 3) / 4, false, false, false, false},
                        Case{"gray4.png", PNG_COLOR_TYPE_GRAY, 4, (w + 1) / 2, false, false, false, false},
                        Case{"gray8_trns.png", PNG_COLOR_TYPE_GRAY, 8, w, false, false, true, false},
                        Case{"rgb16_trns.png", PNG_COLOR_TYPE_RGB, 16, w * 6, false, false, true, false},
                        Case{"rgb8_interlaced.png", PNG_COLOR_TYPE_RGB, 8, w * 3, false, false, false, true},
                        Case{"ga16_interlaced.png", PNG_COLOR_TYPE_GRAY_ALPHA, 16, w * 4, false, false, false, true}}) {
    test::PngVariant v = make(k.color, k.depth, k.row_bytes);
    v.interlaced = k.interlaced;
    if (k.palette) {
      for (int i = 0; i < (1 << k.depth); ++i)
        v.palette.push_back(png_color{static_cast<png_byte>(i * 13), static_cast<png_byte>(255 - i), static_cast<png_byte>(i * 7)});
      for (auto& row : v.rows)
        for (auto& b : row) b = static_cast<png_byte>(k.depth == 8 ? b % v.palette.size() : b);
    }
    if (k.alpha_palette)
      for (int i = 0; i < 5; ++i) v.trans_alpha.push_back(static_cast<png_byte>(i * 50));
    if (k.trans) {
      v.trans_color = true;
      v.trans.gray = 37;
      v.trans.red = 37;
      v.trans.green = 11 * 256 + 48;
      v.trans.blue = 85;
    }
    const fs::path p = dir_ / k.name;
    test::write_png_variant(p, v);
    expect_native_like_oiio(p);
  }
}

TEST_F(NativeCodecs, TiffFromOpenImageIOReadsTheSame) {
  struct Layout {
    const char* name;
    int tile;
    bool separate;
  };
  const OIIO::TypeDesc types[] = {OIIO::TypeDesc::UINT8, OIIO::TypeDesc::UINT16, OIIO::TypeDesc::HALF,
                                  OIIO::TypeDesc::FLOAT, OIIO::TypeDesc::DOUBLE};
  int n = 0;
  for (const Layout& layout : {Layout{"strips", 0, false}, Layout{"tiles", 32, false}, Layout{"planes", 0, true},
                               Layout{"planetiles", 16, true}})
    for (OIIO::TypeDesc type : types)
      for (const char* compression : {"none", "lzw", "zip", "packbits"}) {
        const int channels = 1 + (n++ % 4);
        const fs::path p = dir_ / fmt::format("{}_{}_{}_{}.tif", layout.name, type.c_str(), compression, channels);
        Image image = pattern(70, 45, channels);
        if (type.is_floating_point()) image.data[5] = -3.25f, image.data[7] = 1e6f;  // floats are kept as they are
        oiio_write_with(p, image, type, [&](OIIO::ImageSpec& spec) {
          spec.tile_width = spec.tile_height = layout.tile;
          spec.attribute("Compression", compression);
          if (type == OIIO::TypeDesc::HALF) spec.attribute("tiff:half", 1);
          if (layout.separate) spec.attribute("planarconfig", "separate");
        });
        if (type == OIIO::TypeDesc::DOUBLE && layout.tile > 0) {
          // OpenImageIO 2.4 reads tiled 64-bit float TIFFs wrongly (zeros and misplaced values);
          // compare with the values written instead.
          EXPECT_TRUE(native(p));
          expect_same(image, read_image(p).image, p.filename().string());
          continue;
        }
        expect_native_like_oiio(p);
      }
}

TEST_F(NativeCodecs, TiffVariantsGdpLeavesGoThroughOpenImageIOsModule) {
  for (OIIO::TypeDesc type : {OIIO::TypeDesc::INT16, OIIO::TypeDesc::UINT32, OIIO::TypeDesc::INT8}) {
    const fs::path p = dir_ / fmt::format("{}.tif", type.c_str());
    SCOPED_TRACE(p.filename().string());
    oiio_write_with(p, pattern(40, 30, 3), type, [](OIIO::ImageSpec&) {});
    EXPECT_FALSE(native(p));
    const ReadResult ours = read_image(p);
    expect_same(oiio_read(p), ours.image, p.filename().string());
    EXPECT_EQ(ours.info.format_name, "tiff");
  }
}

TEST_F(NativeCodecs, JpegTiffReadsAsOpenImageIOReadsIt) {
  const fs::path p = dir_ / "jpeg.tif";
  oiio_write_with(p, pattern(64, 48, 3), OIIO::TypeDesc::UINT8,
                  [](OIIO::ImageSpec& spec) { spec.attribute("Compression", "jpeg:90"); });
  expect_native_like_oiio(p);
}

TEST_F(NativeCodecs, JpegFromOpenImageIOReadsTheSame) {
  for (int channels : {1, 3})
    for (bool progressive : {false, true}) {
      const fs::path p = dir_ / fmt::format("c{}{}.jpg", channels, progressive ? "p" : "");
      oiio_write_with(p, pattern(83, 61, channels), OIIO::TypeDesc::UINT8,
                      [&](OIIO::ImageSpec& spec) { spec.attribute("jpeg:progressive", progressive ? 1 : 0); });
      expect_native_like_oiio(p);
    }
}

// Every real PNG and JPEG under tests/data (RGB, RGBA, grey; baseline JPEGs at 4:2:0 and grey).
TEST_F(NativeCodecs, TestDataFilesReadAsOpenImageIOReadsThem) {
  int files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(GDP_TEST_DATA)) {
    const std::string ext = io::lower_extension(entry.path().string());
    if (ext != "png" && ext != "jpg" && ext != "jpeg" && ext != "tif" && ext != "tiff") continue;
    expect_native_like_oiio(entry.path());
    ++files;
  }
  EXPECT_GT(files, 10);
}

// Written by gdp, read back by gdp and by OpenImageIO: the values written, in the sample type expected.
TEST_F(NativeCodecs, RoundTripsPerFormatAndSampleType) {
  struct Case {
    const char* name;
    SampleType asked, stored;
    int channels;
    bool tiled;
    const char* compression;
  };
  for (const Case& k : {Case{"u8.png", SampleType::UInt8, SampleType::UInt8, 1, false, ""},
                        Case{"u8a.png", SampleType::UInt8, SampleType::UInt8, 2, false, ""},
                        Case{"u16.png", SampleType::UInt16, SampleType::UInt16, 3, false, ""},
                        Case{"f.png", SampleType::Float, SampleType::UInt16, 4, false, ""},
                        Case{"u8.tif", SampleType::UInt8, SampleType::UInt8, 3, false, "lzw"},
                        Case{"u16.tif", SampleType::UInt16, SampleType::UInt16, 4, true, "zip"},
                        Case{"h.tif", SampleType::Half, SampleType::Float, 2, false, "none"},
                        Case{"f.tif", SampleType::Float, SampleType::Float, 1, true, "packbits"},
                        Case{"d.tif", SampleType::Double, SampleType::Double, 3, false, ""},
                        Case{"dt.tif", SampleType::Double, SampleType::Double, 3, true, "zip:9"},
                        Case{"zstd.tif", SampleType::UInt16, SampleType::UInt16, 3, false, "zstd"},
                        Case{"lzma.tif", SampleType::Float, SampleType::Float, 1, false, "lzma"},
                        Case{"u16.jpg", SampleType::UInt16, SampleType::UInt8, 3, false, ""}}) {
    SCOPED_TRACE(k.name);
    const fs::path p = dir_ / k.name;
    WriteOptions options;
    options.sample_type = k.asked;
    options.tiled = k.tiled;
    options.tile_size = 32;
    options.compression = k.compression;
    options.jpeg_quality = 100;
    // JPEG subsamples chroma: a smooth image for it, the k / 255 pattern for the lossless formats.
    Image written = pattern(75, 50, k.channels);
    if (std::string(k.name).ends_with(".jpg"))
      for (int c = 0; c < k.channels; ++c)
        for (int y = 0; y < 50; ++y)
          for (int x = 0; x < 75; ++x) written.at(c, x, y) = static_cast<float>(x + 2 * y + 20 * c) / 255.0f;
    write_image(p, written, options);
    const ReadResult ours = read_image(p);
    if (!(k.stored == SampleType::Double && k.tiled)) expect_same(oiio_read(p), ours.image, k.name);  // see above
    EXPECT_EQ(ours.info.sample_type, k.stored);
    EXPECT_EQ(test::oiio_sample_type(p), k.stored);
    // Lossless files give the values written; JPEG (chroma subsampled) close to them on average.
    double error = 0;
    for (std::size_t i = 0; i < written.data.size(); ++i) {
      if (!ours.info.lossy) {
        ASSERT_NEAR(ours.image.data[i], written.data[i], 1e-6f) << "sample " << i;
      }
      error += std::abs(ours.image.data[i] - written.data[i]);
    }
    EXPECT_LT(error / static_cast<double>(written.data.size()), ours.info.lossy ? 0.01 : 1e-6);
    auto in = OIIO::ImageInput::open(p.string());
    ASSERT_TRUE(in);
    EXPECT_EQ(in->spec().tile_width, k.tiled ? 32 : 0);
  }
}

// Deflated strips and tiles are predicted and compressed by gdp on two threads
// (io/tiff_strip_compressor.h): libtiff (gdp's reader) and OpenImageIO must read back the values
// written, for every predictor (horizontal 8/16-bit, floating point 32/64-bit), strip height (32
// rows, fewer for wide floats), a last strip that is not full and tiles past the image's edges.
TEST_F(NativeCodecs, DeflatedStripsAndTilesReadBackAsWritten) {
  struct Case {
    SampleType type;
    int width, height, channels;
    const char* compression;
    int tile;
  };
  for (const Case& k : {Case{SampleType::UInt8, 101, 77, 1, "", 0}, Case{SampleType::UInt8, 64, 200, 4, "zip:9", 0},
                        Case{SampleType::UInt16, 33, 70, 2, "zip", 0}, Case{SampleType::Float, 90, 65, 3, "zip:1", 0},
                        Case{SampleType::Double, 17, 40, 4, "", 0}, Case{SampleType::Float, 30000, 23, 1, "", 0},
                        Case{SampleType::UInt8, 100, 90, 3, "", 32}, Case{SampleType::UInt16, 70, 20, 4, "", 16},
                        Case{SampleType::Float, 50, 50, 2, "", 48}, Case{SampleType::Double, 33, 65, 1, "", 16}}) {
    const fs::path p =
        dir_ / fmt::format("z{}_{}x{}x{}_{}.tif", static_cast<int>(k.type), k.width, k.height, k.channels, k.tile);
    SCOPED_TRACE(p.filename().string());
    Image written = pattern(k.width, k.height, k.channels);
    if (k.type == SampleType::Float || k.type == SampleType::Double)
      for (std::size_t i = 0; i < written.data.size(); i += 7) written.data[i] = -written.data[i] * 1000.0f;
    WriteOptions options;
    options.sample_type = k.type;
    options.compression = k.compression;
    options.tiled = k.tile > 0;
    options.tile_size = k.tile;
    for (bool write_behind : {true, false}) {
      ImageFileWriter writer(p, k.width, k.height, k.channels, options, write_behind);
      const std::vector<std::vector<float>> rows = test::rows_of(written);
      for (int y = 0; y < k.height; ++y) writer.write_row(y, rows[y]);
      writer.commit();
      const Image ours = read_image(p).image;
      if (!(k.type == SampleType::Double && k.tile > 0)) expect_same(oiio_read(p), ours, "gdp against OpenImageIO");
      for (std::size_t i = 0; i < written.data.size(); ++i)
        ASSERT_NEAR(ours.data[i], written.data[i], 1e-6f * std::max(1.0f, std::abs(written.data[i]))) << i;
      auto in = OIIO::ImageInput::open(p.string());
      ASSERT_TRUE(in);
      EXPECT_EQ(in->spec().get_int_attribute("tiff:Compression"), 8);
    }
  }
}

TEST_F(NativeCodecs, TiffCompressionNamesGiveTheirCodecs) {
  for (auto [name, code] : {std::pair{"none", 1}, std::pair{"lzw", 5}, std::pair{"zip", 8}, std::pair{"", 8},
                            std::pair{"packbits", 32773}, std::pair{"deflate", 8}, std::pair{"jpeg", 7}}) {
    const fs::path p = dir_ / fmt::format("c_{}.tif", name);
    WriteOptions options;
    options.sample_type = SampleType::UInt8;
    options.compression = name;
    write_image(p, pattern(40, 20, 3), options);
    auto in = OIIO::ImageInput::open(p.string());
    ASSERT_TRUE(in);
    EXPECT_EQ(in->spec().get_int_attribute("tiff:Compression"), code) << name;
  }
  WriteOptions bogus;
  bogus.compression = "bogus";  // refused before anything is written (it used to give zip)
  EXPECT_THROW(write_image(dir_ / "bogus.tif", pattern(40, 20, 3), bogus), UsageError);
  EXPECT_FALSE(fs::exists(dir_ / "bogus.tif"));
}

TEST_F(NativeCodecs, BigTiffIsWrittenWhenAskedAndReadsBack) {
  const fs::path p = dir_ / "big.tif";
  std::ofstream(p).close();
  auto encoder = io::create_tiff_encoder();
  io::EncodeSpec spec;
  spec.width = 40;
  spec.height = 30;
  spec.channels = 3;
  spec.sample_type = SampleType::UInt16;
  spec.tile_size = 16;
  spec.bigtiff = true;
  encoder->open(p.string(), spec);
  ASSERT_EQ(encoder->stored(), SampleType::UInt16);
  std::vector<std::uint16_t> rows(static_cast<std::size_t>(40) * 32 * 3);
  for (std::size_t i = 0; i < rows.size(); ++i) rows[i] = static_cast<std::uint16_t>(i * 97);
  encoder->write(0, 16, rows.data());
  encoder->write(16, 30, rows.data() + 40 * 16 * 3);
  encoder->close();
  encoder.reset();
  char head[4] = {};
  std::ifstream(p, std::ios::binary).read(head, 4);
  EXPECT_EQ(std::string(head, 4), std::string("II+\0", 4)) << "BigTIFF signature";
  expect_native_like_oiio(p);
  const Image back = read_image(p).image;
  EXPECT_EQ(back.at(1, 5, 7), io::from_u16(static_cast<std::uint16_t>(((7 * 40 + 5) * 3 + 1) * 97)));
}

}  // namespace
}  // namespace gdp
