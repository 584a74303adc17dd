// Helpers for the codec tests: files written by OpenImageIO with chosen attributes, PNG variants written by libpng, comparisons.
#pragma once

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <png.h>

#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "gdp/image.h"
#include "gdp/image_io.h"
#include "image_stream_util.h"

namespace gdp::test {

// The sample type OpenImageIO reports for a file.
inline SampleType oiio_sample_type(const std::filesystem::path& path) {
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) return SampleType::Float;
  switch (in->spec().format.basetype) {
    case OIIO::TypeDesc::UINT8: return SampleType::UInt8;
    case OIIO::TypeDesc::UINT16: return SampleType::UInt16;
    case OIIO::TypeDesc::HALF: return SampleType::Half;
    case OIIO::TypeDesc::DOUBLE: return SampleType::Double;
    default: return SampleType::Float;
  }
}

inline std::string oiio_format_name(const std::filesystem::path& path) {
  auto in = OIIO::ImageInput::open(path.string());
  return in ? in->format_name() : "";
}

// A PNG written by libpng as given: `color` and `depth` as in the file, rows of packed samples
// (16-bit big-endian), an optional palette and tRNS chunk, optionally interlaced.
struct PngVariant {
  int width = 0, height = 0, color = PNG_COLOR_TYPE_GRAY, depth = 8;
  bool interlaced = false;
  std::vector<png_color> palette;
  std::vector<png_byte> trans_alpha;  // palette alpha
  bool trans_color = false;           // gray/RGB tRNS: the colour `trans`
  png_color_16 trans{};
  std::vector<std::vector<png_byte>> rows;
};

inline void write_png_variant(const std::filesystem::path& path, PngVariant& v) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  ASSERT_TRUE(f);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_init_io(png, f);
  png_set_IHDR(png, info, v.width, v.height, v.depth, v.color,
               v.interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  if (!v.palette.empty()) png_set_PLTE(png, info, v.palette.data(), static_cast<int>(v.palette.size()));
  if (!v.trans_alpha.empty())
    png_set_tRNS(png, info, v.trans_alpha.data(), static_cast<int>(v.trans_alpha.size()), nullptr);
  if (v.trans_color) png_set_tRNS(png, info, nullptr, 0, &v.trans);
  png_write_info(png, info);
  std::vector<png_bytep> pointers;
  for (auto& row : v.rows) pointers.push_back(row.data());
  png_write_image(png, pointers.data());
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  std::fclose(f);
}

// Samples equal, with the index of the first difference reported.
inline void expect_same(const Image& expected, const Image& actual, const std::string& what) {
  ASSERT_EQ(expected.width, actual.width) << what;
  ASSERT_EQ(expected.height, actual.height) << what;
  ASSERT_EQ(expected.channels, actual.channels) << what;
  for (std::size_t i = 0; i < expected.data.size(); ++i)
    ASSERT_EQ(expected.data[i], actual.data[i]) << what << ": sample " << i << " of " << expected.data.size();
}

}  // namespace gdp::test
