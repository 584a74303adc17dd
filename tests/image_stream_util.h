// Helpers for the image stream tests: a per-test directory and whole-image I/O through OpenImageIO alone.
#pragma once

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include "gdp/image.h"

namespace gdp::test {

// A fresh directory per test, removed afterwards.
class TempDirTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = std::filesystem::temp_directory_path() /
           ("gdp-image-stream-" + std::to_string(::getpid()) + "-" + info->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ignored;
    std::filesystem::remove_all(dir_, ignored);
  }
  std::set<std::string> names() const {
    std::set<std::string> result;
    for (const auto& entry : std::filesystem::directory_iterator(dir_)) result.insert(entry.path().filename().string());
    return result;
  }
  std::filesystem::path dir_;
};

// Values k / 255 (exact in 8- and 16-bit and float files) varying along rows, columns and channels.
inline Image pattern(int w, int h, int c) {
  Image img(w, h, c);
  for (int ch = 0; ch < c; ++ch)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) img.at(ch, x, y) = static_cast<float>((x * 7 + y * 13 + ch * 101) % 256) / 255.0f;
  return img;
}

// Writes `image` with OpenImageIO (independently of gdp's writer), after `configure` has set the
// spec's attributes (alpha is unassociated).
inline void oiio_write_with(const std::filesystem::path& path, const Image& image, OIIO::TypeDesc type,
                            const std::function<void(OIIO::ImageSpec&)>& configure) {
  const int w = image.width, h = image.height, c = image.channels;
  std::vector<float> pixels(image.data.size());
  for (int ch = 0; ch < c; ++ch)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) pixels[(static_cast<std::size_t>(y) * w + x) * c + ch] = image.at(ch, x, y);
  OIIO::ImageSpec spec(w, h, c, type);
  spec.attribute("oiio:UnassociatedAlpha", 1);
  configure(spec);
  auto out = OIIO::ImageOutput::create(path.string());
  ASSERT_TRUE(out) << path;
  ASSERT_TRUE(out->open(path.string(), spec)) << out->geterror();
  ASSERT_TRUE(out->write_image(OIIO::TypeFloat, pixels.data())) << out->geterror();
  ASSERT_TRUE(out->close()) << out->geterror();
}

// The same, tiled when tile > 0.
inline void oiio_write(const std::filesystem::path& path, const Image& image, OIIO::TypeDesc type, int tile = 0) {
  oiio_write_with(path, image, type, [tile](OIIO::ImageSpec& spec) { spec.tile_width = spec.tile_height = tile; });
}

// An image from interleaved samples (pixel by pixel, channels together).
inline Image from_interleaved(const std::vector<float>& pixels, int w, int h, int c) {
  Image image(w, h, c);
  for (int ch = 0; ch < c; ++ch)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) image.at(ch, x, y) = pixels[(static_cast<std::size_t>(y) * w + x) * c + ch];
  return image;
}

// The whole image as OpenImageIO reads it in one call (alpha unassociated, first subimage).
inline Image oiio_read(const std::filesystem::path& path) {
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(path.string(), &config);
  if (!in) {
    ADD_FAILURE() << OIIO::geterror();
    return {};
  }
  const OIIO::ImageSpec& spec = in->spec();
  std::vector<float> pixels(spec.image_pixels() * spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeFloat, pixels.data())) ADD_FAILURE() << in->geterror();
  return from_interleaved(pixels, spec.width, spec.height, spec.nchannels);
}

// Rows as RowReader::read_row() gives them: channel-major, row[c * width + x].
inline std::vector<std::vector<float>> rows_of(const Image& image) {
  std::vector<std::vector<float>> rows(image.height);
  for (int y = 0; y < image.height; ++y)
    for (int c = 0; c < image.channels; ++c) {
      const auto r = image.row(c, y);
      rows[y].insert(rows[y].end(), r.begin(), r.end());
    }
  return rows;
}

}  // namespace gdp::test
