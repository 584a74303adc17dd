// The pages of a TIFF file with their placement on a larger canvas (as Hugin's nona writes them).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "gdp/image_io.h"

namespace gdp::io {

// One page (directory) of a TIFF file. Cropped layers carry their offset on the canvas as
// XPOSITION/YPOSITION (in resolution units: pixels = position * resolution) and the canvas size
// as PIXAR_IMAGEFULLWIDTH/LENGTH (tags 33300/33301).
struct TiffPage {
  int width = 0, height = 0;
  bool positioned = false;  // XPOSITION or YPOSITION present
  long long x = 0, y = 0;   // offset in pixels (rounded)
  int full_width = 0, full_height = 0;  // 0: no canvas size tags
  std::optional<GeoReference> geo;  // GeoTIFF's georeference (io/tiff_geo.h)
};

// Every page of `path`, or an empty list when it is not a TIFF file. Throws CodecError when
// libtiff cannot read its directories.
std::vector<TiffPage> tiff_pages(const std::string& path);

}  // namespace gdp::io
