// Reading each TIFF page's size, XPOSITION/YPOSITION and PIXAR canvas size tags with libtiff.
#include "io/tiff_pages.h"

#include <cmath>
#include <cstdint>

#include <fmt/format.h>

#include "io/codecs.h"
#include "io/tiff_geo.h"
#include "io/tiff_util.h"

namespace gdp::io {
namespace {

// A position tag in pixels: position (resolution units) times resolution (pixels per unit); a
// missing resolution counts as 1 pixel per unit.
bool position(TIFF* tif, ttag_t tag, ttag_t resolution_tag, long long& pixels) {
  float pos = 0.0f, resolution = 0.0f;
  if (!TIFFGetField(tif, tag, &pos)) return false;
  if (!TIFFGetField(tif, resolution_tag, &resolution) || !(resolution > 0.0f)) resolution = 1.0f;
  pixels = std::llround(static_cast<double>(pos) * resolution);
  return true;
}

}  // namespace

std::vector<TiffPage> tiff_pages(const std::string& path) {
  std::vector<TiffPage> pages;
  if (!is_tiff_file(path)) return pages;
  TiffMessages messages;
  TIFF* tif = TIFFOpenExt(path.c_str(), "rm", messages.options());
  if (!tif) throw CodecError(fmt::format("not a TIFF file libtiff can read ({})", messages.take()));
  do {
    TiffPage p;
    std::uint32_t w = 0, h = 0, full = 0;
    TIFFGetField(tif, TIFFTAG_IMAGEWIDTH, &w);
    TIFFGetField(tif, TIFFTAG_IMAGELENGTH, &h);
    p.width = static_cast<int>(w);
    p.height = static_cast<int>(h);
    const bool px = position(tif, TIFFTAG_XPOSITION, TIFFTAG_XRESOLUTION, p.x);
    const bool py = position(tif, TIFFTAG_YPOSITION, TIFFTAG_YRESOLUTION, p.y);
    p.positioned = px || py;
    if (TIFFGetField(tif, TIFFTAG_PIXAR_IMAGEFULLWIDTH, &full)) p.full_width = static_cast<int>(full);
    full = 0;
    if (TIFFGetField(tif, TIFFTAG_PIXAR_IMAGEFULLLENGTH, &full)) p.full_height = static_cast<int>(full);
    p.geo = read_geotiff(tif);
    pages.push_back(p);
  } while (TIFFReadDirectory(tif));
  TIFFClose(tif);
  return pages;
}

}  // namespace gdp::io
