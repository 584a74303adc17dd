// The pages of a TIFF file with their placement on a larger canvas (as Hugin's nona writes them).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace gdp::io {

// One page (directory) of a TIFF file. Cropped layers carry their offset on the canvas as
// XPOSITION/YPOSITION (in resolution units: pixels = position * resolution) and the canvas size
// as PIXAR_IMAGEFULLWIDTH/LENGTH (tags 33300/33301).
struct TiffPage {
  int width = 0, height = 0;
  bool positioned = false;  // XPOSITION or YPOSITION present
  long long x = 0, y = 0;   // offset in pixels (rounded)
  int full_width = 0, full_height = 0;  // 0: no canvas size tags
  // GeoTIFF (ModelPixelScale 33550 + ModelTiepoint 33922): the model coordinates of the top-left
  // pixel's corner, the pixel size, and the GeoKeyDirectory (34735) that names the CRS.
  struct Geo {
    double origin_x = 0, origin_y = 0, scale_x = 0, scale_y = 0;
    std::vector<std::uint16_t> keys;
  };
  std::optional<Geo> geo;
};

// Every page of `path`, or an empty list when it is not a TIFF file. Throws CodecError when
// libtiff cannot read its directories.
std::vector<TiffPage> tiff_pages(const std::string& path);

}  // namespace gdp::io
