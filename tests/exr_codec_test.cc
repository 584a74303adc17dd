// gdp's own OpenEXR codec: OpenImageIO's pixels and channel order, exact round trips per compression and layout, column windows, a real file.
#include <OpenEXR/ImfRgbaFile.h>
#include <OpenImageIO/imageio.h>
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "cli_fixture.h"
#include "codec_test_util.h"
#include "gdp/errors.h"
#include "gdp/image_io.h"
#include "gdp/image_stream.h"
#include "image_stream_util.h"
#include "io/codecs.h"

namespace gdp {
namespace {

namespace fs = std::filesystem;
using test::expect_same;
using test::oiio_read;
using test::oiio_write_with;
using test::pattern;

const char* const kSample = GDP_TEST_DATA "/polyhaven/park.exr";  // 512 x 256 half RGB, DWAB
const char* const kCompressions[] = {"none", "rle", "zips", "zip", "piz", "pxr24", "b44", "b44a", "dwaa", "dwab"};

// The whole image as gdp's OpenEXR decoder gives it (not OpenImageIO's module).
Image decode(const fs::path& p) {
  auto decoder = io::open_exr_decoder(p.string());
  const io::ImageLayout& l = decoder->layout();
  std::vector<float> pixels(static_cast<std::size_t>(l.width) * l.height * l.channels);
  decoder->read(0, l.height, 0, l.width, pixels.data());
  return test::from_interleaved(pixels, l.width, l.height, l.channels);
}

// Values a half holds exactly: multiples of 1/64 in [-2, 2), with the largest half, a tiny one
// and zero of both signs among them.
Image half_exact(int w, int h, int c) {
  Image image = pattern(w, h, c);
  for (float& v : image.data) v = std::round(v * 255.0f) / 64.0f - 2.0f;
  image.data[1] = 65504.0f, image.data[2] = -std::ldexp(1.0f, -20), image.data[3] = -0.0f;
  return image;
}

// Values most of which no half holds exactly, inside half's range (B44 turns infinities into NaN).
Image spread(int w, int h, int c) {
  Image image = pattern(w, h, c);
  for (float& v : image.data) v = v * 300.0f - 100.0f;
  return image;
}

// Floats no half holds, large and small.
Image floats(int w, int h, int c) {
  Image image = pattern(w, h, c);
  for (std::size_t i = 0; i < image.data.size(); i += 5) image.data[i] = -image.data[i] * 1e7f;
  image.data[1] = 3e38f, image.data[2] = 1e-40f;
  return image;
}

struct OiioHeader {
  std::string compression;
  int tile_width = 0;
  OIIO::TypeDesc format;
  std::vector<std::string> channels;
};

OiioHeader oiio_header(const fs::path& p) {
  auto in = OIIO::ImageInput::open(p.string());
  if (!in) return {};
  const OIIO::ImageSpec& s = in->spec();
  return {s.get_string_attribute("compression"), s.tile_width, s.format, s.channelnames};
}

class ExrCodec : public test::TempDirTest {
 protected:
  // gdp's decoder, and reading through ImageFileReader, give OpenImageIO's pixels and sample type.
  static void expect_like_oiio(const fs::path& p) {
    SCOPED_TRACE(p.filename().string());
    const Image theirs = oiio_read(p);
    expect_same(theirs, decode(p), "decoder");
    const ReadResult ours = read_image(p);
    expect_same(theirs, ours.image, "read_image");
    EXPECT_EQ(ours.info.sample_type, test::oiio_sample_type(p));
    EXPECT_EQ(ours.info.format_name, "openexr");
    EXPECT_FALSE(ours.info.lossy);
  }

  // Every window of `p` read by ImageFileReader equals those columns of the whole image.
  static void expect_windows(const fs::path& p, const std::vector<std::pair<int, int>>& windows) {
    const Image whole = read_image(p).image;
    for (auto [x0, x1] : windows) {
      SCOPED_TRACE(::testing::Message() << p.filename() << " [" << x0 << ", " << x1 << ")");
      ImageFileReader reader(p, x0 % 2 == 0, ColumnRange{x0, x1});
      std::vector<float> row(static_cast<std::size_t>(x1 - x0) * whole.channels);
      for (int y = 0; y < whole.height; ++y) {
        reader.read_row(y, row);
        for (int c = 0; c < whole.channels; ++c)
          for (int x = x0; x < x1; ++x)
            ASSERT_EQ(row[static_cast<std::size_t>(c) * (x1 - x0) + x - x0], whole.at(c, x, y)) << x << " " << y;
      }
    }
  }
};

TEST_F(ExrCodec, FilesFromOpenImageIOReadAsItReadsThem) {
  // 70 x 300: two DWAB blocks (256 rows), a last block and last tiles that are not full.
  int n = 0;
  for (int tile : {0, 32})
    for (OIIO::TypeDesc type : {OIIO::TypeDesc::HALF, OIIO::TypeDesc::FLOAT})
      for (const char* compression : kCompressions) {
        const int channels = 1 + n++ % 4;
        const fs::path p = dir_ / fmt::format("{}_{}_{}_{}.exr", compression, type.c_str(), tile, channels);
        const Image image = type == OIIO::TypeDesc::HALF ? spread(70, 300, channels) : floats(70, 300, channels);
        oiio_write_with(p, image, type, [&](OIIO::ImageSpec& spec) {
          spec.tile_width = spec.tile_height = tile;
          spec.attribute("compression", compression);
        });
        if (channels > 1 || compression[0] != 'd') {  // OpenImageIO 2.4 writes one channel with zip, not DWA
          ASSERT_EQ(oiio_header(p).compression, compression);
        }
        expect_like_oiio(p);
      }
}

TEST_F(ExrCodec, ChannelsComeInOpenImageIOsOrder) {
  struct Case {
    std::vector<std::string> names;
    std::vector<OIIO::TypeDesc> types;  // per channel; empty: all half
  };
  const OIIO::TypeDesc half = OIIO::TypeDesc::HALF, flt = OIIO::TypeDesc::FLOAT, uint = OIIO::TypeDesc::UINT32;
  for (const Case& k : {Case{{"A", "B", "G", "R"}, {}}, Case{{"Y", "A"}, {}}, Case{{"Alpha", "Blue", "Green", "Red"}, {}},
                        Case{{"X", "Y", "Z"}, {}}, Case{{"diffuse.R", "diffuse.G", "diffuse.B", "Z"}, {}},
                        Case{{"U", "V", "w"}, {}}, Case{{"R", "G", "B", "Z"}, {}}, Case{{"N.Z", "N.X", "N.Y", "a"}, {}},
                        Case{{"id"}, {uint}}, Case{{"R", "G", "B"}, {half, flt, uint}}, Case{{"Y", "A"}, {flt, half}}}) {
    const fs::path p = dir_ / fmt::format("{}.exr", fmt::join(k.names, "_"));
    oiio_write_with(p, floats(37, 21, static_cast<int>(k.names.size())), k.types.empty() ? half : k.types[0],
                    [&](OIIO::ImageSpec& spec) {
                      spec.channelnames = k.names;
                      if (k.types.size() > 1) spec.channelformats = k.types;
                    });
    expect_like_oiio(p);
  }
}

TEST_F(ExrCodec, TheDataWindowIsTheImage) {
  const fs::path p = dir_ / "window.exr";
  oiio_write_with(p, floats(40, 30, 3), OIIO::TypeDesc::FLOAT, [](OIIO::ImageSpec& spec) {
    spec.x = 7, spec.y = -5, spec.full_x = 0, spec.full_y = 0, spec.full_width = 100, spec.full_height = 50;
  });
  expect_like_oiio(p);
  EXPECT_EQ(decode(p).width, 40);
}

TEST_F(ExrCodec, MultiPartFilesGiveTheirFirstPart) {
  const fs::path p = dir_ / "parts.exr";
  const Image first = floats(30, 20, 3), second = spread(50, 10, 1);
  OIIO::ImageSpec specs[2] = {OIIO::ImageSpec(30, 20, 3, OIIO::TypeDesc::FLOAT), OIIO::ImageSpec(50, 10, 1, OIIO::TypeDesc::HALF)};
  specs[1].full_width = 30, specs[1].full_height = 20;  // the parts of a file share one display window
  auto out = OIIO::ImageOutput::create(p.string());
  ASSERT_TRUE(out->open(p.string(), 2, specs)) << out->geterror() << OIIO::geterror();
  for (int part = 0; part < 2; ++part) {
    const Image& image = part == 0 ? first : second;
    if (part == 1) {
      ASSERT_TRUE(out->open(p.string(), specs[1], OIIO::ImageOutput::AppendSubimage)) << out->geterror();
    }
    std::vector<float> pixels;
    for (int y = 0; y < image.height; ++y)
      for (int x = 0; x < image.width; ++x)
        for (int c = 0; c < image.channels; ++c) pixels.push_back(image.at(c, x, y));
    ASSERT_TRUE(out->write_image(OIIO::TypeFloat, pixels.data())) << out->geterror();
  }
  ASSERT_TRUE(out->close());
  ASSERT_EQ(OIIO::ImageInput::open(p.string())->spec().get_int_attribute("oiio:subimages"), 2);
  expect_like_oiio(p);
  expect_same(first, decode(p), "first part");
}

// Written by gdp, read back by gdp and by OpenImageIO: exactly the values written, in the layout,
// sample type, compression and channel names asked for. 301 x 420 x 3 is several bands of rows.
TEST_F(ExrCodec, LosslessRoundTripsAreExact) {
  const std::vector<std::vector<std::string>> names = {{"Y"}, {"Y", "A"}, {"R", "G", "B"}, {"R", "G", "B", "A"}};
  int n = 0;
  for (int tile : {0, 16, 64})
    for (SampleType type : {SampleType::Half, SampleType::Float})
      for (const char* compression : {"", "none", "rle", "zips", "zip:9", "piz", "pxr24"}) {
        if (type == SampleType::Float && std::string(compression) == "pxr24") continue;  // 24-bit floats
        const int channels = n++ % 4 == 0 ? 1 : 3 + n % 2;
        const fs::path p = dir_ / fmt::format("rt_{}_{}_{}.exr", tile, static_cast<int>(type), n);
        SCOPED_TRACE(::testing::Message() << p.filename() << " '" << compression << "'");
        const Image written = type == SampleType::Half ? half_exact(301, 420, channels) : floats(301, 420, channels);
        write_image(p, written, WriteOptions{type, 95, tile > 0, compression, tile});
        expect_same(written, read_image(p).image, "gdp");
        expect_same(written, oiio_read(p), "OpenImageIO");
        const OiioHeader header = oiio_header(p);
        const std::string name = std::string(compression).substr(0, std::string(compression).find(':'));
        EXPECT_EQ(header.compression, name.empty() ? "piz" : name);
        EXPECT_EQ(header.tile_width, tile);
        EXPECT_EQ(header.format, type == SampleType::Half ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT);
        EXPECT_EQ(header.channels, names[channels - 1]);
      }
}

TEST_F(ExrCodec, TwoChannelsAreGrayAndAlpha) {
  const fs::path p = dir_ / "ya.exr";
  const Image written = half_exact(20, 10, 2);
  write_image(p, written, WriteOptions{SampleType::Half, 95, false, "", 256});
  expect_same(written, read_image(p).image, "gdp");
  EXPECT_EQ(oiio_header(p).channels, (std::vector<std::string>{"Y", "A"}));
}

TEST_F(ExrCodec, SampleTypesAsOpenImageIOWroteThem) {
  // Integers and half as half, float and double as float; floats never clamped.
  for (auto [asked, stored] : {std::pair{SampleType::UInt8, SampleType::Half}, std::pair{SampleType::UInt16, SampleType::Half},
                               std::pair{SampleType::Double, SampleType::Float}}) {
    const fs::path p = dir_ / fmt::format("t{}.exr", static_cast<int>(asked));
    const Image written = half_exact(30, 20, 3);
    write_image(p, written, WriteOptions{asked, 95, false, "", 256});
    const ReadResult back = read_image(p);
    EXPECT_EQ(back.info.sample_type, stored);
    expect_same(written, back.image, p.filename().string());
  }
  const fs::path p = dir_ / "default.exr";
  write_image(p, floats(30, 20, 1), WriteOptions{});
  EXPECT_EQ(read_image(p).info.sample_type, SampleType::Float);
}

TEST_F(ExrCodec, LossyCompressionsReadAsOpenImageIOReadsThem) {
  for (const char* compression : {"b44", "b44a", "dwaa", "dwab:200", "pxr24"})
    for (SampleType type : {SampleType::Half, SampleType::Float}) {
      const fs::path p = dir_ / fmt::format("lossy_{}_{}.exr", compression, static_cast<int>(type));
      SCOPED_TRACE(p.filename().string());
      Image written = pattern(150, 300, 3);  // smooth enough for DCT and 4x4 blocks
      for (int c = 0; c < 3; ++c)
        for (int y = 0; y < 300; ++y)
          for (int x = 0; x < 150; ++x) written.at(c, x, y) = 0.2f + 0.001f * static_cast<float>(x + y + 30 * c);
      write_image(p, written, WriteOptions{type, 95, false, compression, 256});
      expect_like_oiio(p);
      const Image back = read_image(p).image;
      double error = 0;
      for (std::size_t i = 0; i < written.data.size(); ++i) error += std::abs(back.data[i] - written.data[i]);
      EXPECT_LT(error / static_cast<double>(written.data.size()), 2e-3);
      EXPECT_EQ(oiio_header(p).compression, std::string(compression).substr(0, std::string(compression).find(':')));
    }
}

TEST_F(ExrCodec, TheSampleFileReadsAsOpenImageIOReadsIt) {
  expect_like_oiio(kSample);
  EXPECT_EQ(read_image(kSample).info.sample_type, SampleType::Half);
  // DWAB blocks are 256 rows: every window cuts through them.
  expect_windows(kSample, {{0, 512}, {0, 1}, {100, 301}, {511, 512}});
}

TEST_F(ExrCodec, ColumnWindowsOfTiledAndScanlineFiles) {
  for (int tile : {0, 32, 48}) {
    const fs::path p = dir_ / fmt::format("w{}.exr", tile);
    write_image(p, floats(300, 700, 3), WriteOptions{SampleType::Float, 95, tile > 0, "", tile});
    expect_windows(p, {{0, 300}, {0, 1}, {32, 64}, {70, 100}, {60, 200}, {299, 300}});
  }
}

TEST_F(ExrCodec, SubsampledChannelsAreInputErrors) {
  // Luminance and chroma (Y, RY and BY, the chroma sampled 2 x 2), as OpenEXR's RgbaOutputFile
  // writes them; OpenImageIO 2.4 refuses them too.
  const fs::path p = dir_ / "yc.exr";
  {
    std::vector<Imf::Rgba> pixels(16 * 8, Imf::Rgba(0.5f, 0.25f, 0.125f, 1.0f));
    Imf::RgbaOutputFile file(p.c_str(), 16, 8, Imf::WRITE_YC);
    file.setFrameBuffer(pixels.data(), 1, 16);
    file.writePixels(8);
  }
  try {
    read_image(p);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(p.string() + ": subsampled channels", 0), 0u) << e.what();
  }
}

class ExrCli : public test::CliFixture {};

TEST_F(ExrCli, DamagedFilesFailWithOneLineAndNoOutput) {
  Image image = pattern(200, 300, 3);
  write_image(path("in.exr"), image, WriteOptions{SampleType::Half, 95, false, "piz", 256});
  fs::copy_file(path("in.exr"), path("cut.exr"));
  fs::resize_file(path("cut.exr"), fs::file_size(path("in.exr")) / 2);
  expect_failure("convert " + path("cut.exr") + " -o " + path("out.exr"), "cut.exr: cannot read pixels");
  expect_failure("sharpen " + path("cut.exr") + " --scale 4 -o " + path("out.exr") + " --tiled -q", "cut.exr");
  const test::CliRun ok = gdp("sharpen " + path("in.exr") + " --scale 4 -o " + path("out.exr") + " --tiled -q");
  EXPECT_EQ(ok.code, 0) << ok.err;
  EXPECT_EQ(read_image(path("out.exr")).info.sample_type, SampleType::Half);
}

}  // namespace
}  // namespace gdp
