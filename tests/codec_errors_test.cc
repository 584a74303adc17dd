// Damaged PNG, TIFF and JPEG files are InputErrors naming the file (never crashes); unwritable outputs are OutputErrors.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <set>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "gdp/errors.h"
#include "gdp/image_io.h"
#include "gdp/image_stream.h"
#include "image_stream_util.h"

namespace gdp {
namespace {

namespace fs = std::filesystem;
using test::oiio_write;

class CodecErrors : public test::TempDirTest {
 protected:
  // Noise, so that compressed files are large and every part of them matters.
  static Image noise(int w, int h, int c) {
    Image image(w, h, c);
    std::mt19937 random(3);
    for (float& v : image.data) v = static_cast<float>(random() % 256) / 255.0f;
    return image;
  }

  static void cut(const fs::path& p, double keep) {
    fs::resize_file(p, static_cast<std::uintmax_t>(static_cast<double>(fs::file_size(p)) * keep));
  }

  // Reading the whole file, and streaming it with and without prefetch, is an InputError naming it.
  static void expect_input_error(const fs::path& p) {
    SCOPED_TRACE(p.filename().string());
    auto check = [&](const std::function<void()>& read) {
      try {
        read();
        ADD_FAILURE() << "no error";
      } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()).rfind(p.string() + ": ", 0), 0u) << e.what();
        EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
      }
    };
    check([&] { read_image(p); });
    for (bool prefetch : {true, false})
      check([&] {
        ImageFileReader reader(p, prefetch);
        std::vector<float> row(static_cast<std::size_t>(reader.width()) * reader.channels());
        for (int y = 0; y < reader.height(); ++y) reader.read_row(y, row);
      });
  }
};

TEST_F(CodecErrors, TruncatedFilesAreInputErrors) {
  for (const char* name : {"a.png", "a.jpg", "a.tif", "tiles.tif"}) {
    const fs::path p = dir_ / name;
    oiio_write(p, noise(300, 400, 3), OIIO::TypeDesc::UINT8, std::string(name) == "tiles.tif" ? 64 : 0);
    cut(p, 0.6);
    expect_input_error(p);
  }
}

TEST_F(CodecErrors, AJpegMissingOnlyItsEndMarkerStillReads) {
  const fs::path p = dir_ / "no_eoi.jpg";
  const Image image = noise(100, 70, 3);
  oiio_write(p, image, OIIO::TypeDesc::UINT8);
  const Image whole = read_image(p).image;
  fs::resize_file(p, fs::file_size(p) - 2);  // FF D9
  EXPECT_EQ(read_image(p).image.data, whole.data);
}

TEST_F(CodecErrors, CorruptCompressedDataIsAnInputError) {
  // A deflate-compressed TIFF whose directory is intact but whose middle strips are garbage.
  const fs::path p = dir_ / "garbage.tif";
  write_image(p, noise(300, 400, 3), WriteOptions{SampleType::UInt8, 95, false, "zip", 256, {}});
  {
    std::fstream f(p, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(fs::file_size(p) / 2));
    const std::string junk(20000, '\x5a');
    f.write(junk.data(), static_cast<std::streamsize>(junk.size()));
  }
  expect_input_error(p);
}

TEST_F(CodecErrors, SignaturesFollowedByJunkAreInputErrors) {
  const std::pair<const char*, std::string> files[] = {
      {"junk.png", std::string("\x89PNG\r\n\x1a\n", 8) + std::string(500, 'x')},
      {"junk.tif", std::string("II*\0", 4) + std::string(500, '\x7f')},
      {"junk.jpg", std::string("\xff\xd8\xff\xe0", 4) + std::string(500, '\x01')},
      {"empty.png", std::string("\x89PNG", 4)}};
  for (const auto& [name, bytes] : files) {
    std::ofstream(dir_ / name, std::ios::binary) << bytes;
    expect_input_error(dir_ / name);
  }
}

TEST_F(CodecErrors, OutputsWhereADirectoryIsAFileAreOutputErrors) {
  std::ofstream(dir_ / "file") << "x";
  for (const char* name : {"a.png", "a.tif", "a.jpg", "a.exr"}) {
    const fs::path p = dir_ / "file" / name;
    try {
      write_image(p, noise(20, 10, 3), {});
      ADD_FAILURE() << name << ": no error";
    } catch (const OutputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(p.string() + ": ", 0), 0u) << e.what();
    }
  }
  EXPECT_EQ(names(), std::set<std::string>{"file"});
}

TEST_F(CodecErrors, ChannelsAPngCannotHoldAreOutputErrorsLeavingNothing) {
  try {
    write_image(dir_ / "five.png", Image(4, 4, 5), {});
    ADD_FAILURE() << "no error";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("five.png"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(names().empty());
}

}  // namespace
}  // namespace gdp
