// GeoTIFF's tags read and written with libtiff (no libgeotiff needed for placement and copying).
#pragma once

#include <tiffio.h>

#include <optional>

#include "gdp/image_io.h"

namespace gdp::io {

// The current directory's georeference: ModelPixelScale (33550) and ModelTiepoint (33922), with
// the GeoKeyDirectory (34735) and its parameters (34736, 34737); nothing without the first two.
std::optional<GeoReference> read_geotiff(TIFF* tif);

// Sets those tags on a file being written (before its first strip or tile).
void write_geotiff(TIFF* tif, const GeoReference& geo);

}  // namespace gdp::io
