// An OpenEXR file's data window in its display window: where a cropped layer lies on its canvas.
#pragma once

#include <optional>
#include <string>

namespace gdp::io {

// OpenEXR's windows, in the file's pixel coordinates (which may be negative): the pixels stored
// (data) and the frame they belong to (display). Tools that write cropped layers (Hugin's nona,
// compositing programs) keep the canvas as the display window and the layer's pixels as the data.
struct ExrWindows {
  int data_x = 0, data_y = 0, data_width = 0, data_height = 0;
  int display_x = 0, display_y = 0, display_width = 0, display_height = 0;
};

// The first part's windows, or nullopt when `path` is not an OpenEXR file. Throws CodecError when
// its header cannot be read.
std::optional<ExrWindows> exr_windows(const std::string& path);

}  // namespace gdp::io
