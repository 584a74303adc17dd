// GeoTIFF tags: read as libtiff's anonymous fields, written after registering their field info.
#include "io/tiff_geo.h"

#include <cstdint>
#include <vector>

namespace gdp::io {
namespace {

constexpr ttag_t kPixelScale = 33550, kTiepoint = 33922, kKeys = 34735, kDoubles = 34736, kAscii = 34737;

// An array tag of the current directory (libtiff keeps tags it does not know as anonymous fields:
// a 32-bit count and an array of the type the file gave). A tag of another type (a pixel scale
// stored as SHORTs, say) is taken as absent: its array does not hold T's.
template <class T>
std::vector<T> array_tag(TIFF* tif, ttag_t tag, TIFFDataType type) {
  const TIFFField* field = TIFFFindField(tif, tag, TIFF_ANY);
  if (!field || TIFFFieldDataType(field) != type || !TIFFFieldPassCount(field) ||
      TIFFFieldReadCount(field) != TIFF_VARIABLE2)
    return {};
  std::uint32_t count = 0;
  T* data = nullptr;
  if (!TIFFGetField(tif, tag, &count, &data) || !data) return {};
  return std::vector<T>(data, data + count);
}

}  // namespace

std::optional<GeoReference> read_geotiff(TIFF* tif) {
  const std::vector<double> scale = array_tag<double>(tif, kPixelScale, TIFF_DOUBLE);
  const std::vector<double> tie = array_tag<double>(tif, kTiepoint, TIFF_DOUBLE);
  if (scale.size() < 2 || tie.size() < 6 || !(scale[0] > 0) || !(scale[1] > 0)) return std::nullopt;
  GeoReference g;
  g.scale_x = scale[0];
  g.scale_y = scale[1];
  g.origin_x = tie[3] - tie[0] * scale[0];  // tie point: pixel (I, J) at model (X, Y)
  g.origin_y = tie[4] + tie[1] * scale[1];
  g.keys = array_tag<std::uint16_t>(tif, kKeys, TIFF_SHORT);
  g.double_params = array_tag<double>(tif, kDoubles, TIFF_DOUBLE);
  const std::vector<char> ascii = array_tag<char>(tif, kAscii, TIFF_ASCII);
  g.ascii_params.assign(ascii.begin(), ascii.end());
  while (!g.ascii_params.empty() && g.ascii_params.back() == '\0') g.ascii_params.pop_back();
  return g;
}

void write_geotiff(TIFF* tif, const GeoReference& geo) {
  static TIFFFieldInfo info[] = {
      {kPixelScale, -1, -1, TIFF_DOUBLE, FIELD_CUSTOM, 1, 1, const_cast<char*>("ModelPixelScaleTag")},
      {kTiepoint, -1, -1, TIFF_DOUBLE, FIELD_CUSTOM, 1, 1, const_cast<char*>("ModelTiepointTag")},
      {kKeys, -1, -1, TIFF_SHORT, FIELD_CUSTOM, 1, 1, const_cast<char*>("GeoKeyDirectoryTag")},
      {kDoubles, -1, -1, TIFF_DOUBLE, FIELD_CUSTOM, 1, 1, const_cast<char*>("GeoDoubleParamsTag")},
      {kAscii, -1, -1, TIFF_ASCII, FIELD_CUSTOM, 1, 0, const_cast<char*>("GeoAsciiParamsTag")}};
  TIFFMergeFieldInfo(tif, info, 5);
  double scale[3] = {geo.scale_x, geo.scale_y, 0.0}, tie[6] = {0.0, 0.0, 0.0, geo.origin_x, geo.origin_y, 0.0};
  TIFFSetField(tif, kPixelScale, 3, scale);
  TIFFSetField(tif, kTiepoint, 6, tie);
  if (!geo.keys.empty()) TIFFSetField(tif, kKeys, static_cast<int>(geo.keys.size()), geo.keys.data());
  if (!geo.double_params.empty())
    TIFFSetField(tif, kDoubles, static_cast<int>(geo.double_params.size()), geo.double_params.data());
  if (!geo.ascii_params.empty()) TIFFSetField(tif, kAscii, geo.ascii_params.c_str());
}

}  // namespace gdp::io
