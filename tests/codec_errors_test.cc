// Damaged PNG, TIFF, JPEG and OpenEXR files are InputErrors naming the file (never crashes); unwritable outputs are OutputErrors.
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
  for (const char* name : {"a.png", "a.jpg", "a.tif", "tiles.tif", "a.exr", "tiles.exr"}) {
    const fs::path p = dir_ / name;
    oiio_write(p, noise(300, 400, 3), OIIO::TypeDesc::UINT8, std::string(name).starts_with("tiles") ? 64 : 0);
    cut(p, 0.6);
    expect_input_error(p);
  }
}

TEST_F(CodecErrors, OpenExrFilesCutAnywhereAreInputErrors) {
  // Inside the magic number, the header, the table of block offsets and the blocks; scanline
  // blocks of 16 rows (zip) and 256 rows (the sample's DWAB), tiles.
  const fs::path sample = GDP_SOURCE_DIR "/tests/data/exr/park.exr";
  for (const char* name : {"zip.exr", "tiles.exr", "dwab.exr"}) {
    const fs::path whole = dir_ / (std::string("whole_") + name);
    if (std::string(name) == "dwab.exr") fs::copy_file(sample, whole);
    else write_image(whole, noise(300, 400, 3), WriteOptions{SampleType::Half, 95, name[0] == 't', "", 64});
    const auto size = static_cast<std::uintmax_t>(fs::file_size(whole));
    for (std::uintmax_t keep : {std::uintmax_t{2}, std::uintmax_t{40}, std::uintmax_t{330}, std::uintmax_t{420},
                                size * 3 / 10, size * 6 / 10, size * 95 / 100, size - 1}) {
      const fs::path p = dir_ / (std::to_string(keep) + "_" + name);
      fs::copy_file(whole, p);
      fs::resize_file(p, keep);
      expect_input_error(p);
    }
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

// libjpeg only warns about damaged data (and fills in gray): every such warning is an error, at
// any cut (but where only the end marker is missing) and for flipped bytes, as written by gdp's
// own encoder and by OpenImageIO's.
TEST_F(CodecErrors, DamagedJpegDataIsAnInputError) {
  const Image image = noise(300, 400, 3);
  write_image(dir_ / "gdp.jpg", image, {});
  oiio_write(dir_ / "oiio.jpg", image, OIIO::TypeDesc::UINT8);
  for (const char* name : {"gdp.jpg", "oiio.jpg"}) {
    std::ifstream in(dir_ / name, std::ios::binary);
    const std::string whole(std::istreambuf_iterator<char>(in), {});
    const fs::path p = dir_ / "damaged.jpg";
    const auto write = [&](const std::string& bytes) { std::ofstream(p, std::ios::binary) << bytes; };
    for (double keep : {0.1, 0.3, 0.5, 0.7, 0.9, 0.97, 0.99}) {
      SCOPED_TRACE(std::string(name) + " cut at " + std::to_string(keep));
      write(whole.substr(0, static_cast<std::size_t>(whole.size() * keep)));
      expect_input_error(p);
    }
    write(whole.substr(0, whole.size() - 10));
    expect_input_error(p);
    for (unsigned seed = 1; seed <= 5; ++seed) {
      SCOPED_TRACE(std::string(name) + " flipped, seed " + std::to_string(seed));
      std::string bytes = whole;
      std::mt19937 random(seed);
      for (int i = 0; i < 20; ++i) bytes[1000 + random() % (bytes.size() - 1002)] ^= '\xff';
      write(bytes);
      expect_input_error(p);
    }
  }
}

TEST_F(CodecErrors, CorruptCompressedDataIsAnInputError) {
  // Deflate-compressed files whose directory or header is intact but whose middle blocks are garbage.
  for (const char* name : {"garbage.tif", "garbage.exr"}) {
    const fs::path p = dir_ / name;
    write_image(p, noise(300, 400, 3), WriteOptions{SampleType::UInt8, 95, false, "zip", 256});
    {
      std::fstream f(p, std::ios::in | std::ios::out | std::ios::binary);
      f.seekp(static_cast<std::streamoff>(fs::file_size(p) / 2));
      const std::string junk(20000, '\x5a');
      f.write(junk.data(), static_cast<std::streamsize>(junk.size()));
    }
    expect_input_error(p);
  }
}

// libtiff only warns when compressed data would overrun a row ("Discarding N bytes"): an error
// once pixels are being decoded.
TEST_F(CodecErrors, TiffWarningsWhileDecodingAreInputErrors) {
  const fs::path p = dir_ / "packbits.tif";
  write_image(p, noise(16, 16, 3), WriteOptions{SampleType::UInt8, 95, false, "packbits", 256});
  std::fstream f(p, std::ios::in | std::ios::out | std::ios::binary);
  const auto le = [&](std::streamoff at, int bytes) {
    unsigned char b[4] = {};
    f.seekg(at);
    f.read(reinterpret_cast<char*>(b), bytes);
    std::uint32_t v = 0;
    for (int i = bytes - 1; i >= 0; --i) v = v << 8 | b[i];
    return v;
  };
  const std::uint32_t ifd = le(4, 4), entries = le(ifd, 2);
  std::uint32_t strip = 0;
  for (std::uint32_t i = 0; i < entries; ++i) {
    const std::streamoff e = ifd + 2 + 12 * i;
    if (le(e, 2) != 273) continue;  // StripOffsets: one strip, its offset in the entry
    ASSERT_EQ(le(e + 4, 4), 1u);
    strip = le(e + 2, 2) == 3 ? le(e + 8, 2) : le(e + 8, 4);
  }
  ASSERT_GT(strip, 0u);
  f.seekp(strip);
  f.put('\x81');  // a run of 128 bytes, beyond the row's 48
  f.close();
  expect_input_error(p);
}

TEST_F(CodecErrors, SignaturesFollowedByJunkAreInputErrors) {
  const std::pair<const char*, std::string> files[] = {
      {"junk.png", std::string("\x89PNG\r\n\x1a\n", 8) + std::string(500, 'x')},
      {"junk.tif", std::string("II*\0", 4) + std::string(500, '\x7f')},
      {"junk.jpg", std::string("\xff\xd8\xff\xe0", 4) + std::string(500, '\x01')},
      {"junk.exr", std::string("\x76\x2f\x31\x01\x02\0\0\0", 8) + std::string(500, '\x01')},
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
