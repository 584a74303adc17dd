// Tests for image file reading and atomic writing (gdp/image_io.h over OpenImageIO).
#include <sys/stat.h>
#include <unistd.h>

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "gdp/errors.h"
#include "gdp/image_io.h"

namespace {

namespace fs = std::filesystem;
using gdp::Image;
using gdp::SampleType;

Image make_image(int width, int height, int channels, const std::function<float(int, int, int)>& value) {
  Image image(width, height, channels);
  for (int c = 0; c < channels; ++c)
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) image.at(c, x, y) = value(c, x, y);
  return image;
}

// Values k / levels with k covering 0 .. levels (0 and 1 included) across the image.
Image make_quantised_image(int channels, int levels) {
  const int width = 37, height = 23;
  return make_image(width, height, channels, [=](int c, int x, int y) {
    const long k = (static_cast<long>(y * width + x) * 7919 + c * 104729) % (levels + 1);
    return static_cast<float>(k) / static_cast<float>(levels);
  });
}

// Float values that no integer format keeps: negative, above 1, tiny and large.
Image make_float_image(int channels) {
  return make_image(19, 11, channels, [](int c, int x, int y) {
    return (static_cast<float>(x) - 7.3f) * 1.37f + static_cast<float>(y) * 0.001f - static_cast<float>(c) * 123.456f;
  });
}

// Expects `call` to throw an Error whose message is one line naming `path` and holding `part`
// (when given).
template <class Error, class Call>
void expect_error(Call&& call, const fs::path& path, const char* part = nullptr) {
  try {
    call();
    ADD_FAILURE() << "no error thrown for " << path;
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path.string()), std::string::npos) << message;
    if (part) {
      EXPECT_NE(message.find(part), std::string::npos) << message;
    }
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

// Equality of every sample; reports the first difference. Integer files come back as k * (1 / levels),
// which can differ from k / levels in the last bit, so those compare within 4 ulps (far below one
// quantisation step); float files must match bit for bit.
enum class Match { Exact, Ulps };
void expect_same_pixels(const Image& expected, const Image& actual, Match match = Match::Exact) {
  ASSERT_EQ(expected.width, actual.width);
  ASSERT_EQ(expected.height, actual.height);
  ASSERT_EQ(expected.channels, actual.channels);
  ASSERT_EQ(expected.data.size(), actual.data.size());
  for (std::size_t i = 0; i < expected.data.size(); ++i) {
    if (match == Match::Exact) {
      ASSERT_EQ(expected.data[i], actual.data[i]) << "first difference at sample " << i;
    } else {
      ASSERT_FLOAT_EQ(expected.data[i], actual.data[i]) << "first difference at sample " << i;
    }
  }
}

std::set<std::string> names_in(const fs::path& dir) {
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.insert(entry.path().filename().string());
  return names;
}

class ImageIoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("gdp-image-io-test-" + std::to_string(::getpid()) + "-" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::permissions(dir_, fs::perms::owner_all, fs::perm_options::add, ec);
    fs::remove_all(dir_, ec);
  }

  // Writes, reads back and checks the file's reported sample type and format.
  gdp::ReadResult round_trip(const std::string& name, const Image& image, std::optional<SampleType> type,
                             SampleType expected_type, const std::string& expected_format) {
    const fs::path path = dir_ / name;
    gdp::WriteOptions options;
    options.sample_type = type;
    gdp::write_image(path, image, options);
    gdp::ReadResult result = gdp::read_image(path);
    EXPECT_EQ(result.info.sample_type, expected_type) << name;
    EXPECT_EQ(result.info.format_name, expected_format) << name;
    return result;
  }

  fs::path dir_;
};

TEST_F(ImageIoTest, Png8BitRoundTripIsExactForOneToFourChannels) {
  for (int channels = 1; channels <= 4; ++channels) {
    SCOPED_TRACE(channels);
    const Image image = make_quantised_image(channels, 255);
    const auto result = round_trip("a.png", image, SampleType::UInt8, SampleType::UInt8, "png");
    expect_same_pixels(image, result.image, Match::Ulps);
    EXPECT_FALSE(result.info.lossy);
    // Values read from an 8-bit file survive another round trip bit for bit.
    const auto again = round_trip("b.png", result.image, SampleType::UInt8, SampleType::UInt8, "png");
    expect_same_pixels(result.image, again.image);
  }
}

TEST_F(ImageIoTest, PngDefaultsToEightBit) {
  const Image image = make_quantised_image(3, 255);
  const auto result = round_trip("a.png", image, std::nullopt, SampleType::UInt8, "png");
  expect_same_pixels(image, result.image, Match::Ulps);
}

TEST_F(ImageIoTest, LosslessRoundTripsAreExactForOneToFourChannels) {
  // 16-bit files exact on k/65535 (to a few ulps), float files exact bit for bit.
  struct Case {
    const char* name;
    std::optional<SampleType> requested;
    SampleType expected;
    const char* format;
    bool is_float;
  };
  for (const Case& k : {Case{"a.png", SampleType::UInt16, SampleType::UInt16, "png", false},
                        Case{"a.tif", SampleType::UInt16, SampleType::UInt16, "tiff", false},
                        Case{"a.tiff", std::nullopt, SampleType::Float, "tiff", true},
                        Case{"a.exr", std::nullopt, SampleType::Float, "openexr", true}})
    for (int channels = 1; channels <= 4; ++channels) {
      SCOPED_TRACE(::testing::Message() << k.name << " with " << channels << " channels");
      const Image image = k.is_float ? make_float_image(channels) : make_quantised_image(channels, 65535);
      const auto result = round_trip(k.name, image, k.requested, k.expected, k.format);
      if (k.is_float) expect_same_pixels(image, result.image);
      else expect_same_pixels(image, result.image, Match::Ulps);
      EXPECT_FALSE(result.info.lossy);
    }
}

TEST_F(ImageIoTest, LargeImageRoundTripsAcrossSeveralBands) {
  // Over a million samples, so reading and writing go through more than one band of rows.
  const Image image = make_image(1200, 1001, 2, [](int c, int x, int y) {
    return static_cast<float>(x) * 0.25f - static_cast<float>(y) * 0.5f + static_cast<float>(c) * 1000.0f;
  });
  const auto result = round_trip("large.tif", image, std::nullopt, SampleType::Float, "tiff");
  expect_same_pixels(image, result.image);
}

TEST_F(ImageIoTest, ReadsTiledFileWithOffsetDataWindow) {
  // Large enough (1.2 million samples) to be read in several bands of whole tile rows.
  const fs::path path = dir_ / "tiled.exr";
  const int width = 1000, height = 401, channels = 3;
  std::vector<float> pixels(static_cast<std::size_t>(width) * height * channels);
  for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<float>(i % 100003) * 0.5f - 100.0f;
  {
    OIIO::ImageSpec spec(width, height, channels, OIIO::TypeDesc::FLOAT);
    spec.x = 5;
    spec.y = -3;
    spec.tile_width = 16;
    spec.tile_height = 16;
    auto out = OIIO::ImageOutput::create(path.string());
    ASSERT_TRUE(out);
    ASSERT_TRUE(out->open(path.string(), spec)) << out->geterror();
    ASSERT_TRUE(out->write_image(OIIO::TypeFloat, pixels.data())) << out->geterror();
    ASSERT_TRUE(out->close());
  }
  const auto result = gdp::read_image(path);
  ASSERT_EQ(result.image.width, width);
  ASSERT_EQ(result.image.height, height);
  ASSERT_EQ(result.image.channels, channels);
  for (int c = 0; c < channels; ++c)
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x)
        ASSERT_EQ(result.image.at(c, x, y), pixels[(static_cast<std::size_t>(y) * width + x) * channels + c])
            << c << " " << x << " " << y;
}

TEST_F(ImageIoTest, HalfExrKeepsValuesToHalfPrecision) {
  const Image image = make_float_image(3);
  const auto result = round_trip("a.exr", image, SampleType::Half, SampleType::Half, "openexr");
  ASSERT_EQ(result.image.data.size(), image.data.size());
  for (std::size_t i = 0; i < image.data.size(); ++i) {
    EXPECT_NEAR(result.image.data[i], image.data[i], std::abs(image.data[i]) * 1e-3f) << i;
  }
}

TEST_F(ImageIoTest, FloatRequestedForPngFallsBackTo16Bit) {
  const Image image = make_quantised_image(3, 65535);
  const auto result = round_trip("a.png", image, SampleType::Float, SampleType::UInt16, "png");
  expect_same_pixels(image, result.image, Match::Ulps);
}

TEST_F(ImageIoTest, IntegerOutputsAreClampedToUnitRange) {
  Image image(4, 1, 1);
  image.data = {-0.5f, 1.5f, std::numeric_limits<float>::quiet_NaN(), 0.2f};
  const auto result = round_trip("a.png", image, SampleType::UInt16, SampleType::UInt16, "png");
  EXPECT_EQ(result.image.data[0], 0.0f);
  EXPECT_EQ(result.image.data[1], 1.0f);
  EXPECT_EQ(result.image.data[2], 0.0f);
  EXPECT_NEAR(result.image.data[3], 0.2f, 1.0f / 65535);
}

TEST_F(ImageIoTest, JpegRoundTripIsCloseAndReportedLossy) {
  const Image image = make_image(64, 48, 3, [](int c, int x, int y) {
    return 0.2f + 0.6f * (static_cast<float>(x) / 63.0f) * (c == 1 ? 1.0f : 0.5f) + 0.1f * static_cast<float>(y) / 47.0f;
  });
  const auto result = round_trip("a.jpg", image, std::nullopt, SampleType::UInt8, "jpeg");
  EXPECT_TRUE(result.info.lossy);
  ASSERT_EQ(result.image.data.size(), image.data.size());
  double total_error = 0.0;
  for (std::size_t i = 0; i < image.data.size(); ++i) {
    EXPECT_NEAR(result.image.data[i], image.data[i], 0.05f) << i;
    total_error += std::abs(result.image.data[i] - image.data[i]);
  }
  EXPECT_LT(total_error / static_cast<double>(image.data.size()), 0.01);
}

TEST_F(ImageIoTest, JpegQualityChangesFileSize) {
  const Image noise = make_image(128, 128, 3, [](int c, int x, int y) {
    return static_cast<float>((static_cast<unsigned>(x * 7919 + y * 104729 + c * 15485863) * 2654435761u) % 1000) / 1000.0f;
  });
  gdp::WriteOptions low, high;
  low.jpeg_quality = 10;
  high.jpeg_quality = 95;
  gdp::write_image(dir_ / "low.jpg", noise, low);
  gdp::write_image(dir_ / "high.jpg", noise, high);
  EXPECT_LT(fs::file_size(dir_ / "low.jpg") * 2, fs::file_size(dir_ / "high.jpg"));
}

TEST_F(ImageIoTest, MissingFileIsInputErrorNamingTheFile) {
  const fs::path path = dir_ / "no-such-input.png";
  expect_error<gdp::InputError>([&] { gdp::read_image(path); }, path, "No such file");
}

TEST_F(ImageIoTest, TextFileNamedPngIsInputError) {
  const fs::path path = dir_ / "not-an-image.png";
  std::ofstream(path) << "this is plain text, not a PNG\n";
  expect_error<gdp::InputError>([&] { gdp::read_image(path); }, path);
}

TEST_F(ImageIoTest, FiveChannelFileIsInputError) {
  const fs::path path = dir_ / "five.tif";
  {
    auto out = OIIO::ImageOutput::create(path.string());
    ASSERT_TRUE(out);
    ASSERT_TRUE(out->open(path.string(), OIIO::ImageSpec(4, 3, 5, OIIO::TypeDesc::UINT8)));
    const std::vector<unsigned char> pixels(4 * 3 * 5, 7);
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, pixels.data()));
    ASSERT_TRUE(out->close());
  }
  expect_error<gdp::InputError>([&] { gdp::read_image(path); }, path, "5 channels");
}

TEST_F(ImageIoTest, WritingIntoMissingDirectoryIsOutputErrorAndCreatesNothing) {
  const fs::path path = dir_ / "missing" / "out.png";
  expect_error<gdp::OutputError>([&] { gdp::write_image(path, make_quantised_image(3, 255), {}); }, path,
                                 "no such directory");
  EXPECT_FALSE(fs::exists(dir_ / "missing"));
  EXPECT_TRUE(names_in(dir_).empty());
}

TEST_F(ImageIoTest, WritingIntoReadOnlyDirectoryIsOutputErrorAndCreatesNothing) {
  if (::geteuid() == 0) GTEST_SKIP() << "running as root, which ignores directory permissions";
  fs::permissions(dir_, fs::perms::owner_read | fs::perms::owner_exec | fs::perms::group_read |
                            fs::perms::group_exec | fs::perms::others_read | fs::perms::others_exec);
  const fs::path path = dir_ / "out.png";
  expect_error<gdp::OutputError>([&] { gdp::write_image(path, make_quantised_image(3, 255), {}); }, path,
                                 "Permission denied");
  EXPECT_TRUE(names_in(dir_).empty());
}

TEST_F(ImageIoTest, SuccessfulWriteLeavesOnlyTheOutputFile) {
  gdp::write_image(dir_ / "out.tif", make_float_image(2), {});
  gdp::write_image(dir_ / "out.png", make_quantised_image(4, 255), {});
  EXPECT_EQ(names_in(dir_), (std::set<std::string>{"out.png", "out.tif"}));
}

TEST_F(ImageIoTest, OverwritingReplacesTheFile) {
  const fs::path path = dir_ / "out.png";
  gdp::write_image(path, Image(5, 4, 1, 0.0f), {});
  const Image second = make_quantised_image(3, 255);
  gdp::write_image(path, second, {});
  expect_same_pixels(second, gdp::read_image(path).image, Match::Ulps);
  EXPECT_EQ(names_in(dir_), std::set<std::string>{"out.png"});
}

TEST_F(ImageIoTest, FailedRenameRemovesTheTemporaryFile) {
  // The target is an existing directory: everything is written, then the rename fails.
  const fs::path path = dir_ / "taken.png";
  fs::create_directory(path);
  EXPECT_THROW(gdp::write_image(path, make_quantised_image(3, 255), {}), gdp::OutputError);
  EXPECT_EQ(names_in(dir_), std::set<std::string>{"taken.png"});
  EXPECT_TRUE(fs::is_directory(path));
}

TEST_F(ImageIoTest, FailedOpenRemovesTheTemporaryFile) {
  // The HDR writer only takes 3 or 4 channels; its open() fails after the temporary file exists.
  const fs::path path = dir_ / "two.hdr";
  expect_error<gdp::OutputError>([&] { gdp::write_image(path, make_float_image(2), {}); }, path);
  EXPECT_TRUE(names_in(dir_).empty());
}

TEST_F(ImageIoTest, UnknownExtensionAndEmptyImageAreOutputErrors) {
  EXPECT_THROW(gdp::write_image(dir_ / "out.unknownformat", make_float_image(1), {}), gdp::OutputError);
  EXPECT_THROW(gdp::write_image(dir_ / "out.png", Image(), {}), gdp::OutputError);
  EXPECT_TRUE(names_in(dir_).empty());
}

TEST_F(ImageIoTest, ReadsRealJpegPhoto) {
  const auto result = gdp::read_image(fs::path(GDP_TEST_DATA) / "opencv/weir_1_crop.jpg");
  EXPECT_EQ(result.image.width, 640);
  EXPECT_EQ(result.image.height, 480);
  EXPECT_EQ(result.image.channels, 3);
  EXPECT_EQ(result.info.sample_type, SampleType::UInt8);
  EXPECT_EQ(result.info.format_name, "jpeg");
  EXPECT_TRUE(result.info.lossy);
  float lo = 1.0f, hi = 0.0f;
  for (float v : result.image.data) {
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  EXPECT_GE(lo, 0.0f);
  EXPECT_LE(hi, 1.0f);
  EXPECT_GT(hi - lo, 0.5f);  // a real photo, not a flat image
}

TEST(ImageIoExtension, LossyExtensions) {
  for (const char* name : {"a.jpg", "a.JPG", "b.jpeg", "c.jpe", "d.jfif", "e.webp", "f.heic", "g.HEIF", "h.jp2", "i.j2k"}) {
    EXPECT_TRUE(gdp::is_lossy_extension(name)) << name;
  }
  for (const char* name : {"a.png", "a.tif", "a.exr", "a.hdr", "a.fits", "jpg", "a.jpg.png", "a"}) {
    EXPECT_FALSE(gdp::is_lossy_extension(name)) << name;
  }
}

}  // namespace
