// Small valid PNG, TIFF, JPEG, OpenEXR and FITS files written by gdp's encoders (and Hugin-style multi-page TIFFs).
#include "tools/codec_samples.h"

#include <stdexcept>

#include "gdp/image.h"
#include "gdp/image_io.h"
#include "nona_tiff.h"

namespace gdp::test {
namespace {

namespace fs = std::filesystem;

// A smooth ramp with a little structure, values in [0, 1].
Image ramp(int w, int h, int channels) {
  Image img(w, h, channels);
  for (int c = 0; c < channels; ++c)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) img.at(c, x, y) = static_cast<float>((x * (c + 1) + 3 * y + ((x ^ y) & 3)) % 64) / 63.0f;
  return img;
}

struct Variant {
  const char* name;
  int w, h, channels;
  WriteOptions options;
};

WriteOptions opts(SampleType type, std::string compression = {}, int tile = 0) {
  WriteOptions o;
  o.sample_type = type;
  o.compression = std::move(compression);
  o.tiled = tile > 0;
  if (tile > 0) o.tile_size = tile;
  return o;
}

std::vector<Variant> variants(const std::string& codec) {
  using S = SampleType;
  if (codec == "png")
    return {{"g8", 13, 9, 1, opts(S::UInt8)}, {"rgb16", 11, 7, 3, opts(S::UInt16)}, {"rgba8", 9, 6, 4, opts(S::UInt8)},
            {"ga16", 7, 5, 2, opts(S::UInt16)}};
  if (codec == "tiff") {
    WriteOptions geo = opts(S::Float, "none");
    geo.geo = GeoReference{100.5, 42.0, 0.25, 0.25, {1, 1, 0, 2, 1024, 0, 1, 2, 2048, 0, 1, 4326}, {6378137.0}, "WGS 84|"};
    return {{"f32zip", 13, 9, 1, opts(S::Float)},           {"u16lzw", 11, 7, 3, opts(S::UInt16, "lzw")},
            {"u8none", 9, 6, 4, opts(S::UInt8, "none")},     {"u8packbits", 10, 5, 2, opts(S::UInt8, "packbits")},
            {"u8jpeg", 16, 16, 3, opts(S::UInt8, "jpeg")},   {"f32tiled", 37, 20, 3, opts(S::Float, "zip", 16)},
            {"u16zstd", 12, 8, 1, opts(S::UInt16, "zstd")},  {"geo", 6, 5, 1, geo}};
  }
  if (codec == "jpeg") {
    WriteOptions q = opts(S::UInt8);
    q.jpeg_quality = 80;
    return {{"rgb", 17, 11, 3, q}, {"grey", 9, 8, 1, q}};
  }
  if (codec == "exr")
    return {{"piz", 13, 9, 3, opts(S::Half)},          {"zip", 11, 7, 4, opts(S::Float, "zip")},
            {"rle", 9, 6, 1, opts(S::Half, "rle")},     {"none", 5, 4, 2, opts(S::Float, "none")},
            {"tiled", 37, 20, 3, opts(S::Half, "zips", 16)}, {"pxr24", 8, 8, 3, opts(S::Float, "pxr24")},
            {"b44", 8, 8, 3, opts(S::Half, "b44")},     {"dwaa", 16, 16, 3, opts(S::Half, "dwaa")}};
  if (codec == "fits") {
    WriteOptions wcs = opts(S::Float);
    wcs.fits_header = "CTYPE1  = 'RA---TAN'" + std::string(60, ' ') + "CTYPE2  = 'DEC--TAN'" + std::string(60, ' ');
    return {{"f32", 13, 9, 1, opts(S::Float)}, {"u16", 11, 7, 3, opts(S::UInt16)}, {"u8", 9, 6, 1, opts(S::UInt8)},
            {"wcs", 6, 5, 1, wcs}};
  }
  throw std::invalid_argument("no samples for codec " + codec);
}

const char* extension(const std::string& codec) {
  if (codec == "tiff") return ".tif";
  if (codec == "jpeg") return ".jpg";
  return codec == "png" ? ".png" : codec == "exr" ? ".exr" : ".fits";
}

}  // namespace

const std::vector<std::string>& sample_codecs() {
  static const std::vector<std::string> codecs = {"png", "tiff", "jpeg", "exr", "fits"};
  return codecs;
}

std::vector<fs::path> write_codec_samples(const fs::path& dir, const std::string& codec) {
  std::vector<fs::path> paths;
  for (const Variant& v : variants(codec)) {
    paths.push_back(dir / (codec + "_" + v.name + extension(codec)));
    write_image(paths.back(), ramp(v.w, v.h, v.channels), v.options);
  }
  if (codec == "tiff") {  // two pages placed on a canvas, as Hugin's nona writes layers
    const Image a = ramp(7, 5, 4), b = ramp(6, 6, 2);
    paths.push_back(dir / "tiff_pages.tif");
    write_nona_tiff(paths.back().string(), {{&a, 2, 1, 8}, {&b, 5, 3, 16}}, 16, 12);
  }
  return paths;
}

}  // namespace gdp::test
